//! The errors of the command line, shown through `miette`: a scenario error underlines its
//! line of the scenario file; every other error is its message, which names the file, key
//! or flag, the value and the fix.

use std::path::{Path, PathBuf};

use granular::scenario::ScenarioError;
use miette::{Diagnostic, LabeledSpan, NamedSource, SourceCode};

/// Why a command failed (exit status 2, or 128 + the signal for an interrupted run).
#[derive(Debug)]
pub enum CliError {
    /// A scenario file that does not validate.
    Scenario(Box<BadScenario>),
    /// Any other failure.
    Message(String),
    /// A run stopped by a signal after writing its checkpoint.
    Interrupted {
        /// The exit status: 128 + the signal's number (130 SIGINT, 143 SIGTERM).
        status: u8,
        /// What happened and the command that resumes.
        message: String,
    },
}

/// A scenario file that does not validate, with its text.
#[derive(Debug)]
pub struct BadScenario {
    /// The scenario file.
    path: PathBuf,
    /// Its text, for the snippet around the bad line.
    source: NamedSource<String>,
    /// Whether the bad key was set on the command line.
    overridden: bool,
    /// Whether the bad line and its neighbours are short enough to show (a scenario "file"
    /// of one 20 MB line would otherwise be printed whole).
    snippet_fits: bool,
    /// What is wrong, where.
    error: ScenarioError,
}

impl CliError {
    /// A scenario error in the file `path` whose text is `text`, read with the `--set`
    /// overrides `overrides` (`KEY=VALUE`; an error in an overridden key shows no file line,
    /// since the bad value is not in the file).
    pub fn scenario(path: &Path, text: &str, overrides: &[String], error: ScenarioError) -> Self {
        let overridden = overrides.iter().any(|o| {
            o.split_once('=')
                .is_some_and(|(k, _)| k.trim() == error.key)
        });
        let snippet_fits = error.line.is_some_and(|line| snippet_fits(text, line));
        Self::Scenario(Box::new(BadScenario {
            path: path.to_path_buf(),
            source: NamedSource::new(path.display().to_string(), text.to_string()),
            overridden,
            snippet_fits,
            error,
        }))
    }
}

impl CliError {
    /// The process's exit status for this error.
    pub fn exit_status(&self) -> u8 {
        match self {
            Self::Interrupted { status, .. } => *status,
            _ => 2,
        }
    }
}

impl std::fmt::Display for CliError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Scenario(s) => write!(f, "{}: {}", s.path.display(), s.error),
            Self::Message(m) | Self::Interrupted { message: m, .. } => f.write_str(m),
        }
    }
}

impl std::error::Error for CliError {}

impl From<String> for CliError {
    fn from(message: String) -> Self {
        Self::Message(message)
    }
}

impl From<granular_report::ReportError> for CliError {
    fn from(e: granular_report::ReportError) -> Self {
        Self::Message(e.to_string())
    }
}

/// The longest line (in characters) an error shows from the scenario file; a longer bad
/// line, or a longer line next to it (the snippet shows one on each side), leaves the
/// snippet out: the message still names the file, the line and the key.
const MAX_SNIPPET_LINE: usize = 300;

/// Whether the 1-based line `line` of `text` and its two neighbours are at most
/// [`MAX_SNIPPET_LINE`] characters long.
fn snippet_fits(text: &str, line: usize) -> bool {
    text.lines()
        .enumerate()
        .skip(line.saturating_sub(2))
        .take(3)
        .all(|(_, l)| l.chars().count() <= MAX_SNIPPET_LINE)
}

/// Byte span of the 1-based line `line` of `text` (without its line break).
fn line_span(text: &str, line: usize) -> Option<(usize, usize)> {
    let mut start = 0;
    for (i, l) in text.split_inclusive('\n').enumerate() {
        if i + 1 == line {
            return Some((start, l.trim_end_matches(['\n', '\r']).len()));
        }
        start += l.len();
    }
    None
}

impl Diagnostic for CliError {
    fn source_code(&self) -> Option<&dyn SourceCode> {
        match self {
            Self::Scenario(s) if s.snippet_fits && !s.overridden => Some(&s.source),
            _ => None,
        }
    }

    fn labels(&self) -> Option<Box<dyn Iterator<Item = LabeledSpan> + '_>> {
        let Self::Scenario(s) = self else {
            return None;
        };
        if s.overridden || !s.snippet_fits {
            return None;
        }
        let (start, len) = line_span(s.source.inner(), s.error.line?)?;
        let text = (!s.error.key.is_empty()).then(|| format!("`{}`", s.error.key));
        let label = LabeledSpan::new(text, start, len);
        Some(Box::new(std::iter::once(label)))
    }
}

/// Routes error reports through `miette`, one line per message (no wrapping, so that
/// messages stay searchable in logs).
pub fn install_handler() {
    // Fails only when a handler is already installed, which then stays.
    let _ = miette::set_hook(Box::new(|_| {
        Box::new(miette::MietteHandlerOpts::new().wrap_lines(false).build())
    }));
}

/// Writes `error` to standard error.
pub fn report(error: CliError) {
    if let CliError::Interrupted { message, .. } = &error {
        // Not a failure: the run stopped on request and says how to continue.
        eprintln!("{message}");
        return;
    }
    eprintln!("{:?}", miette::Report::new(error));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_spans() {
        let text = "a = 1\r\nbb = 2\n\nccc = 3";
        assert_eq!(line_span(text, 1), Some((0, 5)));
        assert_eq!(line_span(text, 2), Some((7, 6)));
        assert_eq!(line_span(text, 3), Some((14, 0)));
        assert_eq!(line_span(text, 4), Some((15, 7)));
        assert_eq!(line_span(text, 5), None);
    }

    fn bad_restitution() -> ScenarioError {
        ScenarioError {
            key: "collisions.restitution".into(),
            message: "is 1.2; a restitution coefficient must lie in [0, 1]".into(),
            line: Some(2),
        }
    }

    #[test]
    fn scenario_errors_underline_their_line() {
        let text = "[collisions]\nrestitution = 1.2\n";
        let e = CliError::scenario(Path::new("s.toml"), text, &[], bad_restitution());
        assert_eq!(
            e.to_string(),
            "s.toml: line 2: `collisions.restitution`: is 1.2; a restitution coefficient must lie in [0, 1]"
        );
        assert!(e.source_code().is_some());
        let labels: Vec<LabeledSpan> = e.labels().map(Iterator::collect).unwrap_or_default();
        assert_eq!(labels.len(), 1);
        assert_eq!((labels[0].offset(), labels[0].len()), (13, 17));
        assert_eq!(labels[0].label(), Some("`collisions.restitution`"));
    }

    #[test]
    fn a_line_too_long_to_show_leaves_the_snippet_out() {
        let long = "#".repeat(MAX_SNIPPET_LINE + 1);
        for text in [
            format!("[collisions]\n{long}\nrestitution = 1.2\n"),
            format!("[collisions]\nrestitution = 1.2 {long}\n"),
        ] {
            let line = text
                .lines()
                .position(|l| l.starts_with("restitution"))
                .unwrap()
                + 1;
            let error = ScenarioError {
                line: Some(line),
                ..bad_restitution()
            };
            let e = CliError::scenario(Path::new("s.toml"), &text, &[], error);
            assert!(e.source_code().is_none() && e.labels().is_none());
            assert!(e.to_string().starts_with(&format!("s.toml: line {line}:")));
        }
        // The limit itself is shown.
        let text = format!(
            "[collisions]\nrestitution = 1.2\n{}\n",
            "#".repeat(MAX_SNIPPET_LINE)
        );
        let e = CliError::scenario(Path::new("s.toml"), &text, &[], bad_restitution());
        assert!(e.source_code().is_some());
    }

    #[test]
    fn overridden_keys_show_no_file_line() {
        let text = "[collisions]\nrestitution = 1.0\n";
        let set = ["collisions.restitution=1.2".to_string()];
        let e = CliError::scenario(Path::new("s.toml"), text, &set, bad_restitution());
        assert!(e.source_code().is_none() && e.labels().is_none());
        assert!(e.to_string().contains("is 1.2"));
    }
}
