//! Every WGSL file in shaders/ parses and validates with naga (organ_clip.wgsl appended to
//! organ.wgsl, as the renderer compiles it), so a broken shader fails without a GPU;
//! the renderer embeds exactly those files, and every struct it shares with WGSL has the size naga
//! gives the WGSL struct.

use std::path::Path;

/// A shader's WGSL as the renderer compiles it: organ_clip.wgsl only after organ.wgsl.
fn parse(path: &Path) -> (String, naga::Module) {
    let clip = vbrain::render::ORGAN_CLIP_SHADER.name;
    let src = match path.file_name() {
        Some(name) if name == clip => vbrain::render::organ_source(true),
        _ => std::fs::read_to_string(path).unwrap(),
    };
    let module =
        naga::front::wgsl::parse_str(&src).unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
    (src, module)
}

fn shader_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("shaders")
}

#[test]
fn every_shader_validates() {
    let dir = shader_dir();
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "wgsl"));
    assert!(!files.is_empty(), "no shaders in {}", dir.display());
    for path in &files {
        let (src, module) = parse(path);
        naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::all())
            .validate(&module)
            .unwrap_or_else(|e| panic!("{}: {}", path.display(), e.emit_to_string(&src)));
    }
    // The renderer embeds exactly the files on disk.
    for shader in vbrain::render::SHADERS {
        assert_eq!(std::fs::read_to_string(dir.join(shader.name)).unwrap(), shader.source, "{}", shader.name);
    }
    assert_eq!(files.len(), vbrain::render::SHADERS.len(), "a shader in shaders/ is not used by the renderer");
}

#[test]
fn uniform_structs_match_their_wgsl_sizes() {
    for (file, name, size) in vbrain::render::uniforms::SHARED_STRUCTS {
        let (_, module) = parse(&shader_dir().join(file));
        let found = module.types.iter().find_map(|(_, t)| match &t.inner {
            naga::TypeInner::Struct { span, .. } if t.name.as_deref() == Some(name) => Some(*span as usize),
            _ => None,
        });
        assert_eq!(found, Some(size), "{file}: struct {name} is {found:?} bytes in WGSL, {size} in Rust");
    }
}
