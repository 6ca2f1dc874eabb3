//! [`Animation`]: a sequence of snapshots as an animated GIF, or as an MP4 when `ffmpeg`
//! is installed. Each frame is a [`SnapshotPicture`] with the time in its title.

use std::io::Write;
use std::path::Path;
use std::process::{Command, Stdio};

use granular::engine::Snapshot;
use plotters::prelude::*;

use super::snapshot::{ColourBy, PictureStyle, SnapshotPicture};
use super::{Draw, PlotError, ensure_font};

/// An animation of snapshots sharing one [`PictureStyle`].
///
/// When colouring by speed without a fixed maximum, the colour bar spans the fastest grain
/// of *all* frames, so a colour means the same speed throughout.
///
/// ```no_run
/// # use granular_report::plot::{Animation, PictureStyle};
/// # fn demo(snapshots: &[granular::engine::Snapshot]) -> Result<(), granular_report::plot::PlotError> {
/// Animation::new(snapshots, PictureStyle::new(1.0, 1.0).title("Cooling gas"))
///     .frame_delay_ms(80)
///     .save_gif("cooling.gif")?;
/// # Ok(())
/// # }
/// ```
#[derive(Clone, Debug)]
pub struct Animation<'a> {
    snapshots: &'a [Snapshot],
    style: PictureStyle,
    delay_ms: u32,
}

impl<'a> Animation<'a> {
    /// An animation of `snapshots` (one frame each), 100 ms per frame.
    pub fn new(snapshots: &'a [Snapshot], style: PictureStyle) -> Self {
        Self {
            snapshots,
            style,
            delay_ms: 100,
        }
    }

    /// Time each frame is shown, in milliseconds (at least 10: GIF delays are in 1/100 s).
    pub fn frame_delay_ms(mut self, delay: u32) -> Self {
        self.delay_ms = delay.max(10);
        self
    }

    /// The frames' style, with a speed colour bar fixed across all frames.
    fn frame_style(&self) -> PictureStyle {
        let mut style = self.style.clone();
        if let ColourBy::Speed { max: None } = style.colour_by {
            let vmax = self
                .snapshots
                .iter()
                .map(|s| SnapshotPicture::new(s, style.clone()).max_speed())
                .fold(0.0, f64::max);
            style.colour_by = ColourBy::Speed {
                max: Some(if vmax > 0.0 { vmax } else { 1.0 }),
            };
        }
        style
    }

    fn frames(&self) -> Result<(Vec<SnapshotPicture<'a>>, (u32, u32)), PlotError> {
        if self.snapshots.is_empty() {
            return Err(PlotError::Data(
                "an animation needs at least one snapshot".into(),
            ));
        }
        let style = self.frame_style();
        let frames: Vec<SnapshotPicture<'a>> = self
            .snapshots
            .iter()
            .map(|s| SnapshotPicture::new(s, style.clone()))
            .collect();
        for f in &frames {
            f.check()?;
        }
        // Every frame must have the same size: take the first one's.
        let size = frames[0].size();
        Ok((frames, size))
    }

    /// Writes an animated GIF (looping).
    ///
    /// # Errors
    /// [`PlotError::Data`] for no or inconsistent snapshots, [`PlotError::Draw`] if the file
    /// cannot be written.
    pub fn save_gif(&self, path: impl AsRef<Path>) -> Result<(), PlotError> {
        ensure_font()?;
        let (frames, size) = self.frames()?;
        let root = BitMapBackend::gif(path.as_ref(), size, self.delay_ms)
            .map_err(|e| PlotError::Draw(e.to_string()))?
            .into_drawing_area();
        for frame in &frames {
            root.fill(&WHITE)?;
            frame.draw_on(&root, false)?;
            root.present()?;
        }
        Ok(())
    }

    /// Whether `ffmpeg` can be run (is on `PATH`).
    pub fn ffmpeg_available() -> bool {
        Command::new("ffmpeg")
            .arg("-version")
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status()
            .is_ok_and(|s| s.success())
    }

    /// Writes an H.264 MP4 by piping raw RGB frames into `ffmpeg`. Returns `Ok(false)`
    /// without writing anything when `ffmpeg` is not installed.
    ///
    /// # Errors
    /// As [`Animation::save_gif`]; [`PlotError::Io`] if `ffmpeg` fails.
    pub fn save_mp4(&self, path: impl AsRef<Path>) -> Result<bool, PlotError> {
        if !Self::ffmpeg_available() {
            return Ok(false);
        }
        ensure_font()?;
        let (frames, (w, h)) = self.frames()?;
        let path = path.as_ref();
        let fps = format!("{}", 1000.0 / f64::from(self.delay_ms));
        let io = |context: &str| {
            let context = context.to_string();
            move |source| PlotError::Io { context, source }
        };
        let mut child = Command::new("ffmpeg")
            .args([
                "-y",
                "-loglevel",
                "error",
                "-f",
                "rawvideo",
                "-pix_fmt",
                "rgb24",
            ])
            .args(["-s", &format!("{w}x{h}"), "-framerate", &fps, "-i", "-"])
            // H.264 in yuv420p needs even dimensions.
            .args(["-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2:color=white"])
            .args([
                "-c:v",
                "libx264",
                "-pix_fmt",
                "yuv420p",
                "-movflags",
                "+faststart",
            ])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(io("starting ffmpeg"))?;
        let mut buffer = vec![0u8; w as usize * h as usize * 3];
        let mut result = Ok(());
        if let Some(mut stdin) = child.stdin.take() {
            for frame in &frames {
                {
                    let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
                    root.fill(&WHITE)?;
                    frame.draw_on(&root, false)?;
                    root.present()?;
                }
                if let Err(e) = stdin.write_all(&buffer) {
                    result = Err(e);
                    break;
                }
            }
        }
        let output = child.wait_with_output().map_err(io("waiting for ffmpeg"))?;
        if !output.status.success() {
            return Err(PlotError::Io {
                context: format!("ffmpeg failed writing {}", path.display()),
                source: std::io::Error::other(String::from_utf8_lossy(&output.stderr).into_owned()),
            });
        }
        result.map_err(io("piping frames to ffmpeg"))?;
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::super::snapshot::tests::demo_snapshot;
    use super::super::test_support::temp_dir;
    use super::*;

    #[test]
    fn gif_has_all_frames() {
        let dir = temp_dir("animation");
        let snaps: Vec<Snapshot> = (0..5).map(|i| demo_snapshot(0.3 * f64::from(i))).collect();
        let style = PictureStyle::new(2.0, 1.0)
            .periodic(true, false)
            .colour_by(ColourBy::Speed { max: None })
            .title("Demo")
            .size(600, 360);
        let path = dir.join("demo.gif");
        Animation::new(&snaps, style.clone())
            .frame_delay_ms(200)
            .save_gif(&path)
            .expect("gif");
        let mut options = gif::DecodeOptions::new();
        options.set_color_output(gif::ColorOutput::RGBA);
        let mut decoder = options
            .read_info(std::fs::File::open(&path).expect("open gif"))
            .expect("gif header");
        assert_eq!((decoder.width(), decoder.height()), (600, 360));
        let mut frames = 0;
        while let Some(frame) = decoder.read_next_frame().expect("gif frame") {
            assert_eq!(frame.delay, 20);
            if frames == 2 {
                // Keep one frame as PNG for looking at.
                let rgb: Vec<u8> = frame
                    .buffer
                    .chunks(4)
                    .flat_map(|p| [p[0], p[1], p[2]])
                    .collect();
                let file = std::fs::File::create(dir.join("frame2.png")).expect("png");
                let mut enc =
                    png::Encoder::new(file, u32::from(frame.width), u32::from(frame.height));
                enc.set_color(png::ColorType::Rgb);
                enc.write_header()
                    .and_then(|mut w| w.write_image_data(&rgb))
                    .expect("write png");
            }
            frames += 1;
        }
        assert_eq!(frames, 5);
        assert!(
            Animation::new(&[], style.clone())
                .save_gif(dir.join("none.gif"))
                .is_err()
        );
        // MP4 only where ffmpeg exists; otherwise nothing is written.
        let mp4 = dir.join("demo.mp4");
        let written = Animation::new(&snaps, style).save_mp4(&mp4).expect("mp4");
        assert_eq!(written, mp4.exists());
    }
}
