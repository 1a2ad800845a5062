//! `blocksmith doc --format html`: the Markdown reference as one standalone HTML page. Reads
//! only the Markdown the reference writes: headings, fenced code, lists, paragraphs, inline
//! code and links.

use super::reference::slug;

/// A whole page (title, a little style, the body) from the reference's Markdown.
#[must_use]
pub fn page(markdown: &str) -> String {
    let title = markdown.lines().next().and_then(|l| l.strip_prefix("# ")).unwrap_or("blocksmith script reference");
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>{}</title>\n<style>\n\
         body {{ font-family: system-ui, sans-serif; max-width: 60rem; margin: 2rem auto; padding: 0 1rem; line-height: 1.45; }}\n\
         pre {{ background: #f4f4f4; padding: 0.6rem; overflow-x: auto; }}\n\
         code {{ font-family: ui-monospace, monospace; }}\n\
         h3, h4 {{ margin-top: 2rem; border-top: 1px solid #ddd; padding-top: 0.5rem; }}\n\
         </style>\n</head>\n<body>\n{}</body>\n</html>\n",
        escape(title),
        body(markdown)
    )
}

/// The HTML of the Markdown subset the reference writes.
#[must_use]
pub fn body(markdown: &str) -> String {
    let mut out = String::new();
    let mut lines = markdown.lines().peekable();
    let mut paragraph: Vec<&str> = Vec::new();
    // Heading anchors, unique as GitHub makes them: a repeated one gets -1, -2...
    let mut ids: std::collections::HashMap<String, usize> = std::collections::HashMap::new();
    let flush = |paragraph: &mut Vec<&str>, out: &mut String| {
        if !paragraph.is_empty() {
            out.push_str(&format!("<p>{}</p>\n", inline(&paragraph.join("\n"))));
            paragraph.clear();
        }
    };
    while let Some(line) = lines.next() {
        if let Some(lang) = line.strip_prefix("```") {
            flush(&mut paragraph, &mut out);
            let mut code = Vec::new();
            for l in lines.by_ref() {
                if l.trim_start() == "```" {
                    break;
                }
                code.push(escape(l));
            }
            let class = if lang.is_empty() { String::new() } else { format!(" class=\"language-{lang}\"") };
            out.push_str(&format!("<pre><code{class}>{}</code></pre>\n", code.join("\n")));
        } else if let Some(code) = line.strip_prefix("    ").filter(|_| paragraph.is_empty()) {
            // An indented block (not a paragraph's continuation): code.
            let mut code = vec![escape(code)];
            while let Some(l) = lines.peek().and_then(|l| l.strip_prefix("    ")) {
                code.push(escape(l));
                lines.next();
            }
            out.push_str(&format!("<pre><code>{}</code></pre>\n", code.join("\n")));
        } else if line.starts_with('#') && line.contains("# ") {
            flush(&mut paragraph, &mut out);
            let level = line.chars().take_while(|c| *c == '#').count().min(6);
            let text = line[level..].trim();
            let id = slug(&text.replace('`', ""));
            let id = if id.is_empty() {
                String::new()
            } else {
                let seen = ids.entry(id.clone()).or_default();
                *seen += 1;
                let id = if *seen == 1 { id } else { format!("{id}-{}", *seen - 1) };
                format!(" id=\"{}\"", escape(&id))
            };
            out.push_str(&format!("<h{level}{id}>{}</h{level}>\n", inline(text)));
        } else if line.starts_with("- ") {
            flush(&mut paragraph, &mut out);
            out.push_str("<ul>\n");
            let mut item = line.strip_prefix("- ").unwrap_or(line).to_string();
            loop {
                match lines.peek() {
                    Some(l) if l.starts_with("- ") => {
                        out.push_str(&format!("<li>{}</li>\n", inline(&item)));
                        item = l[2..].to_string();
                    }
                    Some(l) if l.starts_with("  ") && !l.trim().is_empty() => {
                        item.push('\n');
                        item.push_str(l.trim());
                    }
                    _ => break,
                }
                lines.next();
            }
            out.push_str(&format!("<li>{}</li>\n</ul>\n", inline(&item)));
        } else if line.trim().is_empty() {
            flush(&mut paragraph, &mut out);
        } else {
            paragraph.push(line);
        }
    }
    flush(&mut paragraph, &mut out);
    out
}

/// Inline Markdown: `code` spans and [text](#anchor) links; everything else escaped.
fn inline(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('`') {
            if let Some(end) = after.find('`') {
                out.push_str(&format!("<code>{}</code>", escape(&after[..end])));
                rest = &after[end + 1..];
                continue;
            }
        }
        if let Some(after) = rest.strip_prefix('[') {
            if let Some((label, tail)) = after.split_once("](") {
                if let Some((href, tail)) = tail.split_once(')') {
                    if !label.contains(['[', '`']) && !href.contains(char::is_whitespace) {
                        out.push_str(&format!("<a href=\"{}\">{}</a>", escape(href), escape(label)));
                        rest = tail;
                        continue;
                    }
                }
            }
        }
        let c = rest.chars().next().unwrap_or_default();
        out.push_str(&escape(&c.to_string()));
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// `text` with `&`, `<`, `>` and `"` escaped.
fn escape(text: &str) -> String {
    text.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;").replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn markdown_subset_becomes_html() {
        let md = "# Title\n\nSome `a < b` text\nand more.\n\n```rhai\nlet x = [1] < 2;\n```\n\n- [Mesh](#mesh) (3)\n- two\n\n    cargo run\n\n### `+`\n\n## Title\n";
        let html = body(md);
        assert!(html.contains("<h1 id=\"title\">Title</h1>"), "{html}");
        assert!(html.contains("<p>Some <code>a &lt; b</code> text\nand more.</p>"), "{html}");
        assert!(html.contains("<pre><code class=\"language-rhai\">let x = [1] &lt; 2;</code></pre>"), "{html}");
        assert!(html.contains("<ul>\n<li><a href=\"#mesh\">Mesh</a> (3)</li>\n<li>two</li>\n</ul>"), "{html}");
        assert!(html.contains("<pre><code>cargo run</code></pre>"), "{html}");
        assert!(html.contains("<h3><code>+</code></h3>"), "{html}");
        assert!(html.contains("<h2 id=\"title-1\">Title</h2>"), "{html}");
        assert!(page(md).starts_with("<!DOCTYPE html>") && page(md).contains("<title>Title</title>"));
    }
}
