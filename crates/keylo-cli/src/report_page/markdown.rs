//! The Markdown keylo writes (`compare.md`: headings, pipe tables, paragraphs, lists, inline
//! code and bold) as HTML. Not a general Markdown renderer.

use super::html::escape;

/// `md` as HTML.
pub fn to_html(md: &str) -> String {
    let mut out = String::new();
    let mut table: Vec<Vec<String>> = Vec::new();
    let mut list = false;
    for line in md.lines().map(str::trim_end) {
        if !line.starts_with('|') && !table.is_empty() {
            out.push_str(&render_table(&table));
            table.clear();
        }
        if !line.starts_with("- ") && list {
            out.push_str("</ul>");
            list = false;
        }
        if line.starts_with('|') {
            let cells = cells(line);
            if !cells
                .iter()
                .all(|c| !c.is_empty() && c.chars().all(|ch| "-: ".contains(ch)))
            {
                table.push(cells);
            }
        } else if let Some(item) = line.strip_prefix("- ") {
            if !list {
                out.push_str("<ul>");
                list = true;
            }
            out.push_str(&format!("<li>{}</li>", inline(item)));
        } else if let Some(h) = line.strip_prefix('#') {
            let level = 1 + h.chars().take_while(|c| *c == '#').count();
            let text = h.trim_start_matches('#').trim();
            let level = (level + 1).min(6); // the page's own h1/h2 come first
            out.push_str(&format!("<h{level}>{}</h{level}>", inline(text)));
        } else if !line.is_empty() {
            out.push_str(&format!("<p>{}</p>", inline(line)));
        }
    }
    if !table.is_empty() {
        out.push_str(&render_table(&table));
    }
    if list {
        out.push_str("</ul>");
    }
    out
}

/// The cells of a pipe-table row; `\|` is a pipe inside a cell.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|');
    let inner = inner
        .strip_suffix('|')
        .filter(|s| !s.ends_with('\\'))
        .unwrap_or(inner);
    let (mut out, mut cell) = (Vec::new(), String::new());
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                cell.push('|');
                chars.next();
            }
            '|' => out.push(std::mem::take(&mut cell)),
            c => cell.push(c),
        }
    }
    out.push(cell);
    out.into_iter().map(|c| c.trim().to_string()).collect()
}

fn render_table(rows: &[Vec<String>]) -> String {
    let mut out = String::from("<table>");
    for (i, row) in rows.iter().enumerate() {
        let tag = if i == 0 { "th" } else { "td" };
        out.push_str("<tr>");
        for c in row {
            out.push_str(&format!("<{tag}>{}</{tag}>", inline(c)));
        }
        out.push_str("</tr>");
    }
    out.push_str("</table>");
    out
}

/// Escapes `text`, then turns `code` and **bold** into tags.
fn inline(text: &str) -> String {
    let mut out = String::new();
    for (i, part) in escape(text).split('`').enumerate() {
        if i % 2 == 1 {
            out.push_str(&format!("<code>{part}</code>"));
        } else {
            for (j, p) in part.split("**").enumerate() {
                if j % 2 == 1 {
                    out.push_str(&format!("<b>{p}</b>"));
                } else {
                    out.push_str(p);
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_headings_lists_and_inline_marks() {
        let md = "# keylo compare\n\n## Accuracy\n\n| a | b<c |\n|---|---|\n| 1 | `x` |\n\n- **one**\n- two\ntext";
        assert_eq!(cells("| a \\| b | c |"), ["a | b", "c"]);
        let html = to_html(md);
        assert!(
            html.contains("<h2>keylo compare</h2><h3>Accuracy</h3>"),
            "{html}"
        );
        assert!(html.contains("<table><tr><th>a</th><th>b&lt;c</th></tr><tr><td>1</td><td><code>x</code></td></tr></table>"), "{html}");
        assert!(
            html.contains("<ul><li><b>one</b></li><li>two</li></ul><p>text</p>"),
            "{html}"
        );
    }
}
