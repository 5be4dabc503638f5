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
    asset!("dose.js", JS),
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
    asset!("i18n.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/index.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/bundle.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/builtins.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/memoizer.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/resolver.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/resource.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/scope.js", JS),
    asset!("vendor/fluent-bundle-0.19.1/types.js", JS),
    asset!(
        "vendor/fluent-bundle-0.19.1/LICENSE",
        "text/plain; charset=utf-8"
    ),
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

/// `GET /console/{path}`: one of the embedded files, a language's words
/// (`l10n/<tag>.ftl`, [`words`]), 404 for anything else.
pub(crate) async fn asset(Path(path): Path<String>) -> Response {
    if let Some(file) = path.strip_prefix("l10n/") {
        return words(file);
    }
    match ASSETS.iter().find(|a| a.path == path) {
        Some(a) => file(a.content_type, a.bytes),
        None => (StatusCode::NOT_FOUND, "no such file").into_response(),
    }
}

/// `GET /console/l10n/<tag>.ftl`: the console's whole catalogue of one language (every
/// `crates/i18n/console/<tag>/*.ftl`, `en-XA` the pseudo-locale made from English); an
/// unknown tag is a 404 naming the languages there are.
fn words(file: &str) -> Response {
    let Some(tag) = file.strip_suffix(".ftl") else {
        return (
            StatusCode::NOT_FOUND,
            "no such file: a language's words are at /console/l10n/<tag>.ftl",
        )
            .into_response();
    };
    match i18n::console_catalogue(tag) {
        Ok(text) => {
            let mut r = text.into_response();
            r.headers_mut()
                .insert(header::CONTENT_TYPE, HeaderValue::from_static(FTL));
            r
        }
        Err(e) => (
            StatusCode::NOT_FOUND,
            format!("{e} (and the pseudo-locale {})", i18n::PSEUDO),
        )
            .into_response(),
    }
}

const FTL: &str = "text/plain; charset=utf-8";

#[cfg(test)]
mod tests {
    use super::{ASSETS, CSS, JS};

    /// Every module the console imports is embedded (a missing one would 404 in the browser).
    #[test]
    fn every_imported_module_is_embedded() {
        for a in ASSETS.iter().filter(|a| a.content_type == JS) {
            let text = std::str::from_utf8(a.bytes).unwrap();
            // The vendored Fluent imports its own files relatively (`./bundle.js`).
            let dir = a.path.rsplit_once('/').map_or("", |(d, _)| d);
            for import in text.split("from \"./").skip(1) {
                let path = format!("{dir}/{}", import.split('"').next().unwrap());
                assert!(
                    ASSETS.iter().any(|b| b.path == path),
                    "{} imports {path}, which is not embedded",
                    a.path
                );
            }
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
