//! A self-contained HTML page of a result: the headline number, the text output, the plots as
//! inline SVG and the notes; no scripts, no files beside it.

/// What the page holds.
pub struct Page<'a> {
    pub title: &'a str,
    /// The one line that matters (the azimuth, the fitted terms), shown first.
    pub headline: &'a str,
    /// The command's text output.
    pub text: &'a str,
    /// SVG documents, inlined as they are.
    pub svgs: &'a [String],
    pub notes: &'a [String],
}

/// `&`, `<`, `>` and `"` as HTML entities.
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

impl Page<'_> {
    pub fn html(&self) -> String {
        let mut h = String::from("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n");
        h += &format!("<title>{}</title>\n", escape(self.title));
        h += "<style>body{font-family:sans-serif;max-width:60em;margin:2em auto;color:#222}\
              #headline{font-size:1.4em;padding:.5em;border-left:4px solid #1f77b4;background:#f4f8fb}\
              pre{background:#f7f7f7;padding:1em;overflow-x:auto}svg{max-width:100%;height:auto}</style>\n";
        h += "</head>\n<body>\n";
        h += &format!("<h1>{}</h1>\n", escape(self.title));
        h += &format!("<p id=\"headline\">{}</p>\n", escape(self.headline));
        for svg in self.svgs {
            // The XML declaration is not allowed inside HTML.
            let body = svg.trim_start().strip_prefix("<?xml").map_or(svg.as_str(), |rest| {
                rest.split_once("?>").map_or(svg.as_str(), |(_, after)| after)
            });
            h += &format!("<figure>{body}</figure>\n");
        }
        h += &format!("<h2>Output</h2>\n<pre id=\"output\">{}</pre>\n", escape(self.text));
        if !self.notes.is_empty() {
            h += "<h2>Notes</h2>\n<ul id=\"notes\">\n";
            for n in self.notes {
                h += &format!("<li>{}</li>\n", escape(n));
            }
            h += "</ul>\n";
        }
        h += "</body>\n</html>\n";
        h
    }

    pub fn write(&self, path: &str) -> Result<(), String> {
        std::fs::write(path, self.html()).map_err(|e| format!("cannot write the report {path}: {e}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_escaped_and_svg_inlined_without_its_declaration() {
        let svgs = vec!["<?xml version=\"1.0\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\"></svg>".to_string()];
        let notes = vec!["a < b & c".to_string()];
        let p = Page {
            title: "fit of <run>",
            headline: "psi 65.5 deg",
            text: "x < y",
            svgs: &svgs,
            notes: &notes,
        };
        let h = p.html();
        assert!(h.contains("<title>fit of &lt;run&gt;</title>"));
        assert!(h.contains("x &lt; y") && h.contains("a &lt; b &amp; c"));
        assert!(h.contains("<figure>\n<svg") && !h.contains("<?xml"));
    }
}
