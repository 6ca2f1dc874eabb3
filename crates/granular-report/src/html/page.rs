//! The frame of a report page: HTML escaping, the inline style sheet, sections, tables and
//! the figures of `granular plot` embedded as inline SVG. Everything the page needs is in
//! the one file: no external style sheet, script, font or image.

use std::fmt::Write;
use std::path::Path;

/// The hand-written style sheet, inlined into every page.
const STYLE: &str = include_str!("report.css");

/// Escapes text for HTML element content and attribute values.
pub(crate) fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            _ => out.push(c),
        }
    }
    out
}

/// A number as the report prints it: 6 significant digits, `—` when not finite.
pub(crate) fn number(x: f64) -> String {
    if !x.is_finite() {
        return "—".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10();
    if (-3.0..6.0).contains(&magnitude) {
        let decimals = (5 - magnitude.floor() as i32).clamp(0, 8) as usize;
        let s = format!("{x:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{x:.5e}")
    }
}

/// A number for the notes of a table: `digits` significant digits (`0.12`, `1.7e-5` as
/// `0.000017`), `—` when not finite.
pub(crate) fn short(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return "—".into();
    }
    if x == 0.0 {
        return "0".into();
    }
    let magnitude = x.abs().log10().floor() as i32;
    if !(-6..6).contains(&magnitude) {
        return format!("{:.*e}", digits.saturating_sub(1), x);
    }
    let decimals = (digits as i32 - 1 - magnitude).max(0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// An HTML page under construction: a title, a navigation bar and sections.
pub(crate) struct Page {
    title: String,
    subtitle: String,
    nav: Vec<(String, String)>,
    body: String,
}

impl Page {
    pub(crate) fn new(title: &str, subtitle: &str) -> Self {
        Self {
            title: title.into(),
            subtitle: subtitle.into(),
            nav: Vec::new(),
            body: String::new(),
        }
    }

    /// Adds a section with its own anchor `id` and heading; `html` is its (trusted) content.
    pub(crate) fn section(&mut self, id: &str, heading: &str, html: &str) {
        self.nav.push((id.into(), heading.into()));
        let _ = write!(
            self.body,
            "<section id=\"{id}\"><h2>{}</h2>\n{html}\n</section>\n",
            escape(heading)
        );
    }

    /// The whole page; `script` (trusted) is appended at the end of the body.
    pub(crate) fn finish(self, script: &str) -> String {
        let mut nav = String::new();
        for (id, heading) in &self.nav {
            let _ = write!(nav, "<a href=\"#{id}\">{}</a>", escape(heading));
        }
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
             <title>{title}</title>\n<style>\n{STYLE}</style>\n</head>\n<body>\n\
             <header><h1>{title}</h1><p class=\"subtitle\">{subtitle}</p><nav>{nav}</nav></header>\n\
             <main>\n{body}</main>\n<footer>Written by granular {version} (<code>granular report</code>); \
             one self-contained file: it loads nothing from the network.</footer>\n{script}</body>\n</html>\n",
            title = escape(&self.title),
            subtitle = escape(&self.subtitle),
            body = self.body,
            version = env!("CARGO_PKG_VERSION"),
        )
    }
}

/// An HTML table; `header` and the cells are trusted HTML (escape text first).
pub(crate) fn table(class: &str, header: &[&str], rows: &[Vec<String>]) -> String {
    let mut out = format!("<div class=\"scroll\"><table class=\"{class}\"><thead><tr>");
    for h in header {
        let _ = write!(out, "<th>{h}</th>");
    }
    out.push_str("</tr></thead><tbody>");
    for row in rows {
        out.push_str("<tr>");
        for cell in row {
            let _ = write!(out, "<td>{cell}</td>");
        }
        out.push_str("</tr>");
    }
    out.push_str("</tbody></table></div>");
    out
}

/// The SVG figures of `figures/` (as `granular plot` wrote them), inline, in file-name
/// order; files whose stem starts with one of `skip` are left out.
pub(crate) fn figures(dir: &Path, skip: &[&str]) -> String {
    let mut files: Vec<_> = std::fs::read_dir(dir.join("figures"))
        .map(|rd| {
            rd.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|x| x == "svg"))
                .collect()
        })
        .unwrap_or_default();
    files.sort();
    let mut out = String::from("<div class=\"figures\">");
    for f in files {
        let stem = f
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().to_string());
        if skip.iter().any(|s| stem.starts_with(s)) {
            continue;
        }
        let Ok(svg) = std::fs::read_to_string(&f) else {
            continue;
        };
        // Drop an XML prolog; the page's style sheet sizes the figure.
        let Some(start) = svg.find("<svg") else {
            continue;
        };
        let _ = writeln!(
            out,
            "<figure><svg class=\"figure\"{}<figcaption>figures/{}.svg</figcaption></figure>",
            &svg[start + 4..],
            escape(&stem)
        );
    }
    out.push_str("</div>");
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escapes_markup() {
        assert_eq!(escape("a<b & \"c\"'"), "a&lt;b &amp; &quot;c&quot;&#39;");
    }

    #[test]
    fn numbers_keep_six_digits() {
        assert_eq!(number(1.0), "1");
        assert_eq!(number(0.123456789), "0.123457");
        assert_eq!(number(12345.678), "12345.7");
        assert_eq!(number(f64::NAN), "—");
        assert_eq!(number(1.5e-7), "1.50000e-7");
    }
}
