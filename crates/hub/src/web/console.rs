//! The therapist console's browser side: static files embedded in the binary (no CDN, no
//! separate web server), served at `/` and `/console/…` beside the API. Its libraries are
//! vendored at pinned versions with their licences (`crates/hub/console/vendor/README.md`).

use axum::extract::Path;
use axum::http::{HeaderValue, StatusCode, header};
use axum::response::{IntoResponse, Response};

/// One embedded file: its path under `/console/`, content type and bytes.
struct Asset {
    path: &'static str,
    content_type: &'static str,
    bytes: &'static [u8],
}

macro_rules! asset {
    ($path:literal, $type:expr) => {
        Asset {
            path: $path,
            content_type: $type,
            bytes: include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/console/", $path)),
        }
    };
}

const JS: &str = "text/javascript; charset=utf-8";
const CSS: &str = "text/css; charset=utf-8";

const ASSETS: &[Asset] = &[
    asset!("app.js", JS),
    asset!("api.js", JS),
    asset!("live.js", JS),
    asset!("live-road.js", JS),
    asset!("live-strength.js", JS),
    asset!("legend.js", JS),
    asset!("replay.js", JS),
    asset!("exercises.js", JS),
    asset!("arm3d.js", JS),
    asset!("charts.js", JS),
    asset!("schema.js", JS),
    asset!("messages.js", JS),
    asset!("clinic.js", JS),
    asset!("clinic.css", CSS),
    asset!("caseload.js", JS),
    asset!("attention.css", CSS),
    asset!("words.js", JS),
    asset!("notes.js", JS),
    asset!("assist.js", JS),
    asset!("wheel.js", JS),
    asset!("progress.js", JS),
    asset!("scales.js", JS),
    asset!("sessionchart.js", JS),
    asset!("replays.js", JS),
    asset!("prescribe.js", JS),
    asset!("patient-settings.js", JS),
    asset!("names.js", JS),
    asset!("names-page.js", JS),
    asset!("audit.js", JS),
    asset!("style.css", CSS),
    asset!("vendor/three-0.181.2/three.module.min.js", JS),
    asset!("vendor/three-0.181.2/three.core.min.js", JS),
    asset!("vendor/three-0.181.2/LICENSE", "text/plain; charset=utf-8"),
    asset!("vendor/uplot-1.6.32/uPlot.esm.js", JS),
    asset!("vendor/uplot-1.6.32/uPlot.min.css", CSS),
    asset!("vendor/uplot-1.6.32/LICENSE", "text/plain; charset=utf-8"),
];

const INDEX: &[u8] = include_bytes!(concat!(env!("CARGO_MANIFEST_DIR"), "/console/index.html"));

/// The console's only policy: scripts, styles, images and connections from this origin only;
/// no inline script or style, no framing, forms only to this origin.
pub(crate) const CONTENT_SECURITY_POLICY: &str = "default-src 'none'; script-src 'self'; \
    style-src 'self'; img-src 'self' data:; connect-src 'self'; base-uri 'none'; \
    form-action 'self'; frame-ancestors 'none'";

fn file(content_type: &'static str, bytes: &'static [u8]) -> Response {
    let mut r = bytes.into_response();
    r.headers_mut()
        .insert(header::CONTENT_TYPE, HeaderValue::from_static(content_type));
    r
}

/// `GET /`: the console's page.
pub(crate) async fn index() -> Response {
    file("text/html; charset=utf-8", INDEX)
}

/// `GET /console/{path}`: one of the embedded files, 404 for anything else.
pub(crate) async fn asset(Path(path): Path<String>) -> Response {
    match ASSETS.iter().find(|a| a.path == path) {
        Some(a) => file(a.content_type, a.bytes),
        None => (StatusCode::NOT_FOUND, "no such file").into_response(),
    }
}

#[cfg(test)]
mod tests {
    use super::{ASSETS, CSS, JS};

    /// Every module the console imports is embedded (a missing one would 404 in the browser).
    #[test]
    fn every_imported_module_is_embedded() {
        for a in ASSETS.iter().filter(|a| a.content_type == JS) {
            let text = std::str::from_utf8(a.bytes).unwrap();
            for import in text.split("from '/console/").skip(1) {
                let path = import.split('\'').next().unwrap();
                assert!(
                    ASSETS.iter().any(|b| b.path == path),
                    "{} imports {path}, which is not embedded",
                    a.path
                );
            }
        }
        assert!(ASSETS.iter().any(|a| a.content_type == CSS));
    }
}
