//! Versioned JSON documents (scene files, lessons), written atomically and read with their format
//! checked first.
//!
//! - Text with keys in the order of the structs, two-space indents and a final newline.
//! - Read with the `"format"` key checked first, so a file of a newer version, of another kind or
//!   not JSON at all gets its own message naming the file (and the line, where there is one).

use crate::error::{Error, Result};
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::Path;

/// Parses `text` as a document of `format` (e.g. `vbrain-scene/1`), a vbrain `kind` ("scene");
/// `path` names it in errors.
pub fn parse<T: DeserializeOwned>(text: &str, path: &Path, format: &str, kind: &str) -> Result<T> {
    let value: serde_json::Value =
        serde_json::from_str(text).map_err(|e| Error::parse(path, Some(e.line()), e.to_string()))?;
    let (family, ours) = format.split_once('/').unwrap_or((format, ""));
    let version = |v: &str| v.parse::<u32>().ok();
    // Only a well-formed later version of the same family is "newer".
    let newer = |f: &str| {
        f.strip_prefix(family)
            .and_then(|rest| rest.strip_prefix('/'))
            .and_then(version)
            .is_some_and(|v| version(ours).is_some_and(|o| v > o))
    };
    match value.get("format").and_then(|f| f.as_str()) {
        Some(f) if f == format => {}
        Some(f) if newer(f) => {
            return Err(Error::parse(
                path,
                None,
                format!("format \"{f}\": written by a newer vbrain (this one reads {format})"),
            ))
        }
        Some(f) => return Err(Error::parse(path, None, format!("format \"{f}\" is not a vbrain {kind}"))),
        None => return Err(Error::parse(path, None, format!("no \"format\": not a vbrain {kind}"))),
    }
    serde_json::from_str(text).map_err(|e| Error::parse(path, Some(e.line()), e.to_string()))
}

/// The JSON text of `value`. (Plain data does not fail to encode; if it did, the error would
/// name `path`.)
pub fn to_json<T: Serialize>(value: &T, path: &Path) -> Result<String> {
    let mut s =
        serde_json::to_string_pretty(value).map_err(|e| Error::Encode { path: path.into(), message: e.to_string() })?;
    s.push('\n');
    Ok(s)
}

/// Writes `value`'s JSON text to `path` atomically.
pub fn save<T: Serialize>(value: &T, path: &Path) -> Result<()> {
    let text = to_json(value, path)?;
    crate::atomic::write(path, |w| w.write_all(text.as_bytes()))
}

/// Serde's default for keys that are true when absent (`caps`).
pub(crate) fn yes() -> bool {
    true
}

/// Leaves such a key out when it holds its default.
pub(crate) fn is_true(b: &bool) -> bool {
    *b
}
