//! The page, built by Vite from web/ (its TypeScript source) into web/dist, embedded in the binary so that
//! `wrinkle paint` needs nothing beside it. CI rebuilds web/dist and checks it matches (tests/page.rs).

const FILES: [(&str, &[u8], &str); 3] = [
    ("index.html", include_bytes!("../web/dist/index.html"), "text/html; charset=utf-8"),
    ("app.js", include_bytes!("../web/dist/assets/app.js"), "text/javascript; charset=utf-8"),
    ("app.css", include_bytes!("../web/dist/assets/app.css"), "text/css; charset=utf-8"),
];

/// A file of the built page by name, with its MIME type.
pub fn file(name: &str) -> Option<(&'static [u8], &'static str)> {
    FILES.iter().find(|f| f.0 == name).map(|f| (f.1, f.2))
}
