//! The report page: sections of HTML, the 3-D scenes, and the assets that make it work
//! offline (styles, three.js, the page's own script), all in one file.

use super::html::escape;
use super::scene::Scene;

static STYLE: &str = include_str!("../../assets/report/report.css");
static ERRORS: &str = include_str!("../../assets/report/errors.js");
static THREE: &str = include_str!("../../assets/three/three-keylo.min.js");
static THREE_LICENCE: &str = include_str!("../../assets/three/LICENSE");
static VIEWS: &str = include_str!("../../assets/report/views.js");

/// One titled part of the page.
pub struct Section {
    pub title: String,
    pub html: String,
}

/// A whole report.
#[derive(Default)]
pub struct Page {
    pub title: String,
    /// Lines under the title (escaped here).
    pub subtitle: Vec<String>,
    pub sections: Vec<Section>,
    pub scenes: Vec<Scene>,
}

impl Page {
    pub fn section(&mut self, title: &str, html: String) {
        self.sections.push(Section {
            title: title.into(),
            html,
        });
    }

    /// Adds a 3-D view and returns the element that shows it, with a legend of its layers.
    pub fn scene(&mut self, scene: Scene) -> String {
        let mut legend = String::new();
        for c in &scene.clouds {
            legend.push_str(&legend_item(&c.colour, &c.name, &c.describe()));
        }
        for l in &scene.lines {
            legend.push_str(&legend_item(
                &l.colour,
                &l.name,
                &format!("{} poses", l.poses),
            ));
        }
        let html = format!(
            "<div class=\"view\" data-scene=\"{}\" title=\"{}\"></div>\
             <ul class=\"legend\">{legend}</ul>\
             <p class=\"hint\">Drag to rotate, right-drag (or shift-drag) to pan, wheel to zoom.</p>",
            self.scenes.len(),
            escape(&scene.title)
        );
        self.scenes.push(scene);
        html
    }

    /// The page as one HTML document.
    pub fn render(&self) -> String {
        let mut body = String::new();
        body.push_str(&format!("<h1>{}</h1>", escape(&self.title)));
        for line in &self.subtitle {
            body.push_str(&format!("<p class=\"sub\">{}</p>", escape(line)));
        }
        body.push_str("<nav>");
        for (i, s) in self.sections.iter().enumerate() {
            body.push_str(&format!("<a href=\"#s{i}\">{}</a>", escape(&s.title)));
        }
        body.push_str("</nav>");
        for (i, s) in self.sections.iter().enumerate() {
            body.push_str(&format!(
                "<section id=\"s{i}\"><h2>{}</h2>{}</section>",
                escape(&s.title),
                s.html
            ));
        }
        // Inside a script element no `<` may open a tag or comment (`</script>`, `<!--`);
        // these characters only occur inside JSON strings, where \u escapes mean the same.
        let scenes = serde_json::to_string(&self.scenes)
            .unwrap_or_else(|_| "[]".into())
            .replace('<', "\\u003c")
            .replace('>', "\\u003e")
            .replace('&', "\\u0026");
        format!(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
             <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\
             <title>{title}</title><script>{ERRORS}</script><style>{STYLE}</style></head>\
             <body>{body}\
             <script type=\"application/json\" id=\"keylo-scenes\">{scenes}</script>\
             <script>/* three.js r187 (npm `three` 0.187.0), bundled with esbuild.\n\
             {THREE_LICENCE}*/\n{THREE}</script><script>{VIEWS}</script></body></html>\n",
            title = escape(&self.title),
        )
    }
}

fn legend_item(colour: &str, name: &str, what: &str) -> String {
    format!(
        "<li><span class=\"swatch\" style=\"background:{}\"></span>{}: {}</li>",
        escape(colour),
        escape(name),
        escape(what)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::report_page::scene::Cloud;

    #[test]
    fn names_cannot_end_the_scene_script_or_open_a_comment() {
        let mut page = Page::default();
        let name = "</script><!--<script>&";
        let scene = Scene {
            title: name.into(),
            clouds: vec![Cloud::thinned(name, "#fff", 1.0, &[[0.0; 3]], 10)],
            lines: Vec::new(),
        };
        page.scene(scene);
        let html = page.render();
        let start = html.find("id=\"keylo-scenes\">").expect("scene data") + 18;
        let end = start + html[start..].find("</script>").expect("its end");
        let json = &html[start..end];
        assert!(!json.contains(['<', '>', '&']), "{json}");
        let back: serde_json::Value = serde_json::from_str(json).expect("valid JSON");
        assert_eq!(back[0]["title"], name);
        assert!(html.contains("Copyright"), "three.js's licence notice");
    }
}
