//! Every WGSL file in shaders/ parses and validates with naga, so a broken shader fails without a GPU.

#![allow(clippy::unwrap_used, clippy::expect_used)] // test helpers may panic

#[test]
fn every_shader_validates() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "wgsl"));
    assert!(!files.is_empty(), "no shaders in {}", dir.display());
    for path in &files {
        let src = std::fs::read_to_string(path).unwrap();
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
    }
    // The renderer embeds exactly the files on disk.
    for (name, src) in vbrain::render::SHADERS {
        assert_eq!(std::fs::read_to_string(dir.join(name)).unwrap(), *src, "{name}");
    }
    assert_eq!(files.len(), vbrain::render::SHADERS.len(), "a shader in shaders/ is not used by the renderer");
}
