//! SCORM 1.2 packages: a web page with a quiz ([`crate::web_page`]) zipped with the
//! `imsmanifest.xml` a learning platform (Moodle, Canvas, Blackboard) reads to import it as one
//! graded activity. The page itself talks to the platform (`web/page.js`: it finds the `API`
//! object on a parent or opener window, reports `cmi.core.score.raw`, `min`, `max` and
//! `cmi.core.lesson_status`, then finishes); this module only packages it.
//!
//! - One organisation, one item, one resource (a SCO whose launch file is `index.html`), every
//!   file of the zip listed in the resource.
//! - The pass mark goes in the item's `adlcp:masteryscore` (whole per cent, 0..=100).
//! - Every text is XML-escaped; zip entries carry a fixed date, so a package's bytes depend only
//!   on the page.

use crate::web_page::Page;
use crate::{Error, Result};
use std::io::Write;
use std::path::Path;

/// The manifest's file name, at the root of the package.
pub const MANIFEST: &str = "imsmanifest.xml";

/// The manifest of a package holding `files` (paths relative to the package's root, the launch
/// file `index.html` among them) under the title `title`.
pub fn manifest(title: &str, pass_mark: f32, files: &[String]) -> String {
    let title = crate::web_page::escape_markup(title);
    let mastery = pass_mark.clamp(0.0, 100.0).round() as u32;
    let mut listed = String::new();
    for f in files {
        listed.push_str(&format!("      <file href=\"{}\"/>\n", crate::web_page::escape_markup(f)));
    }
    format!(
        r#"<?xml version="1.0" encoding="UTF-8"?>
<manifest identifier="vbrain-package" version="1.0"
  xmlns="http://www.imsproject.org/xsd/imscp_rootv1p1p2"
  xmlns:adlcp="http://www.adlnet.org/xsd/adlcp_rootv1p2"
  xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
  xsi:schemaLocation="http://www.imsproject.org/xsd/imscp_rootv1p1p2 imscp_rootv1p1p2.xsd http://www.imsglobal.org/xsd/imsmd_rootv1p2p1 imsmd_rootv1p2p1.xsd http://www.adlnet.org/xsd/adlcp_rootv1p2 adlcp_rootv1p2.xsd">
  <metadata>
    <schema>ADL SCORM</schema>
    <schemaversion>1.2</schemaversion>
  </metadata>
  <organizations default="vbrain-organization">
    <organization identifier="vbrain-organization">
      <title>{title}</title>
      <item identifier="vbrain-item" identifierref="vbrain-resource" isvisible="true">
        <title>{title}</title>
        <adlcp:masteryscore>{mastery}</adlcp:masteryscore>
      </item>
    </organization>
  </organizations>
  <resources>
    <resource identifier="vbrain-resource" type="webcontent" adlcp:scormtype="sco" href="index.html">
{listed}    </resource>
  </resources>
</manifest>
"#
    )
}

/// The package of `page` as zip bytes: its files and the manifest. The page must have a quiz.
pub fn package(page: &Page) -> std::io::Result<Vec<u8>> {
    let pass_mark = page.quiz.as_ref().map_or(crate::lesson::DEFAULT_PASS_MARK, |q| q.pass_mark);
    let files = crate::web_page::files(page);
    let names: Vec<String> = files.iter().map(|(name, _)| name.clone()).collect();
    let manifest = manifest(&page.title, pass_mark, &names);
    let mut zip = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
    let options = zip::write::FileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default());
    for (name, bytes) in
        std::iter::once((MANIFEST, manifest.as_bytes())).chain(files.iter().map(|(n, b)| (n.as_str(), b.as_slice())))
    {
        zip.start_file(name, options)?;
        zip.write_all(bytes)?;
    }
    Ok(zip.finish()?.into_inner())
}

/// Writes the package of `page` to the new file `out` (atomically, and only as a new file, so that
/// another writer's file is never replaced); gives its size in bytes.
pub fn write(out: &Path, page: &Page) -> Result<usize> {
    let bytes = package(page).map_err(|e| Error::io(out, e))?;
    crate::atomic::write_new(out, |w| w.write_all(&bytes))?;
    Ok(bytes.len())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_text_in_the_manifest() {
        let m = manifest("A & <B> \"]]>", 66.6, &["index.html".into(), "odd <&>.js".into()]);
        assert!(m.contains("<title>A &amp; &lt;B&gt; &quot;]]&gt;</title>"), "{m}");
        assert!(m.contains("<file href=\"odd &lt;&amp;&gt;.js\"/>"), "{m}");
        assert!(m.contains("<adlcp:masteryscore>67</adlcp:masteryscore>"), "{m}");
        assert!(!m.contains("]]>"));
    }
}
