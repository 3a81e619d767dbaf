//! Reading `.obj` and `.vbo` mesh files.
//!
//! - Organ space, as written in the file.
//! - **VBO** (Virtual Brain Object, after the thesis) is the OBJ subset vbrain writes: UTF-8 text,
//!   one statement per line, `#` comments, and only these statements:
//!
//! ```text
//! o NAME            start an object (one organ); NAME is the rest of the line
//! g NAME            same as `o` (kept for compatibility)
//! v X Y Z           a vertex position, in millimetres (RAS)
//! vn X Y Z          a vertex normal (need not be unit length)
//! f A//A B//B C//C  a triangle; 1-based indices into the v and vn lists so far,
//!                   or negative (relative)
//! ```
//!
//! - A `.vbo` file is read exactly like an `.obj` file, so any OBJ reader opens it.
//! - vbrain reads the wider OBJ found in the wild: CRLF line ends, `v/vt/vn`, `v//vn`, `v/vt` and
//!   `v` face references, negative indices, quads and n-gons (fan-triangulated), `vt`, `l`, `s`,
//!   `p`, `usemtl`, `mtllib` (a missing material file is a warning), vertex colours after `v`, and
//!   scientific notation.
//! - Reading happens in two steps: [`check`] walks the lines and rejects what is malformed with the
//!   line number (bad or non-finite numbers, zero or out-of-range indices, faces of fewer than
//!   three vertices, non-UTF-8 or binary bytes, no faces at all); then `tobj` builds the meshes.

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use std::path::Path;

/// One object of a file: its name (from `o`/`g`, else the file stem) and mesh.
#[derive(Debug)]
pub struct ObjObject {
    pub name: String,
    pub mesh: Mesh,
}

/// The result of reading a file: its objects, and warnings that did not stop the load.
#[derive(Debug, Default)]
pub struct ObjFile {
    pub objects: Vec<ObjObject>,
    pub warnings: Vec<String>,
}

/// The largest vertex coordinate a mesh may have, millimetres (1 km): beyond it the camera's depth
/// range and the shading lose their precision.
pub const MAX_COORDINATE: f32 = 1e6;

/// Memory loading one triangle takes at most, in the OBJ reader and the mesh: three vertices of
/// its own (position and normal), three indices, and its share of the hierarchy.
const BYTES_PER_TRIANGLE: u64 = 160;
/// And one `v`, `vt` or `vn` line, as the reader holds it.
const BYTES_PER_VERTEX: u64 = 16;

/// Reads an OBJ or VBO file from disk.
pub fn read(path: &Path) -> Result<ObjFile> {
    let bytes = crate::input::read(path, crate::input::Kind::Mesh)?;
    let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    parse(&bytes, path, &stem)
}

/// Parses OBJ/VBO bytes; `path` names the file in errors, `default_name` names objects without `o`/`g`.
pub fn parse(bytes: &[u8], path: &Path, default_name: &str) -> Result<ObjFile> {
    let text = check(bytes, path)?;
    let missing = std::cell::RefCell::new(Vec::new());
    let loader = |mtl: &Path| {
        missing.borrow_mut().push(format!(
            "{}: material library {} not loaded (materials are not used)",
            path.display(),
            mtl.display()
        ));
        Err(tobj::LoadError::OpenFileFailed)
    };
    let (models, _) = tobj::load_obj_buf(&mut text.as_bytes(), &tobj::GPU_LOAD_OPTIONS, loader)
        .map_err(|e| Error::parse(path, None, format!("OBJ reader: {e}")))?;
    let mut objects: Vec<ObjObject> = Vec::new();
    let mut degenerate: Option<String> = None;
    for model in models {
        let m = model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let positions: Vec<[f32; 3]> = m.positions.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect();
        let mut mesh = Mesh { normals: Vec::new(), indices: m.indices, positions };
        if m.normals.len() == m.positions.len() {
            mesh.normals = m.normals.chunks_exact(3).map(|n| [n[0], n[1], n[2]]).collect();
            // A zero normal in the file cannot shade: compute them all instead.
            if mesh.normals.iter().any(|n| glam::Vec3::from(*n).try_normalize().is_none()) {
                mesh.compute_normals();
            }
        } else {
            mesh.compute_normals();
        }
        mesh.validate().map_err(|e| Error::parse(path, None, e.to_string()))?;
        let name =
            if model.name.is_empty() || model.name == "unnamed_object" { default_name.to_string() } else { model.name };
        if !has_area(&mesh) {
            // Nothing to draw, and no bounds to frame: left out, like a broken file of a folder.
            let problem =
                format!("every triangle of \"{name}\" has zero area (its vertices coincide or lie on a line)");
            missing.borrow_mut().push(format!("{}: {problem}: left out", path.display()));
            degenerate.get_or_insert(problem);
            continue;
        }
        // tobj splits an object at each `usemtl`; pieces of one name are one organ again.
        match objects.iter_mut().find(|o| o.name == name) {
            Some(o) => o.mesh.append(&mesh),
            None => objects.push(ObjObject { name, mesh }),
        }
    }
    if objects.is_empty() {
        return Err(Error::parse(path, None, degenerate.unwrap_or_else(|| "no faces".into())));
    }
    Ok(ObjFile { objects, warnings: missing.into_inner() })
}

/// Does some triangle of `mesh` have an area?
fn has_area(mesh: &Mesh) -> bool {
    mesh.indices.chunks_exact(3).any(|t| {
        let p = |i: u32| glam::Vec3::from(mesh.positions[i as usize]);
        (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length_squared() > 0.0
    })
}

/// Validates every line; returns the text for `tobj` on success (polyline `l` and point `p`
/// statements blanked, since `tobj` would read them as faces), or the first problem with its line.
pub fn check<'a>(bytes: &'a [u8], path: &Path) -> Result<std::borrow::Cow<'a, str>> {
    if bytes.is_empty() {
        return Err(Error::parse(path, None, "empty file"));
    }
    let mut counts = [0usize; 3]; // v, vt, vn
    let mut faces = 0usize;
    // Triangles the faces become (a face of n vertices makes n - 2).
    let mut triangles = 0u64;
    let mut has_lines = false;
    for (n, raw) in bytes.split(|&b| b == b'\n').enumerate() {
        let line_no = n + 1;
        let err = |m: String| Error::parse(path, Some(line_no), m);
        if raw.contains(&0) {
            return Err(err("binary data (NUL byte): not a text mesh file".into()));
        }
        let line = std::str::from_utf8(raw).map_err(|_| err("not UTF-8 text".into()))?;
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let args: Vec<&str> = words.collect();
        match keyword {
            "v" => {
                let nums = floats(&args, line_no, path)?;
                if ![3, 4, 6].contains(&nums.len()) {
                    return Err(err(format!(
                        "`v` needs 3 coordinates (optionally w or r g b), found {} numbers",
                        nums.len()
                    )));
                }
                if nums.len() == 4 && nums[3] == 0.0 {
                    return Err(err("`v` with w = 0".into()));
                }
                if let Some(c) = nums[..3].iter().find(|c| c.abs() > MAX_COORDINATE) {
                    return Err(err(format!(
                        "coordinate {c} is beyond +-{MAX_COORDINATE} mm (1 km); vbrain's meshes are in millimetres"
                    )));
                }
                counts[0] += 1;
            }
            "vt" => {
                floats(&args, line_no, path)?;
                counts[1] += 1;
            }
            "vn" => {
                let nums = floats(&args, line_no, path)?;
                if nums.len() != 3 {
                    return Err(err(format!("`vn` needs 3 numbers, found {}", nums.len())));
                }
                counts[2] += 1;
            }
            "f" | "l" | "p" => {
                let min = match keyword {
                    "f" => 3,
                    "l" => 2,
                    _ => 1,
                };
                if args.len() < min {
                    return Err(err(format!("`{keyword}` needs at least {min} vertices, found {}", args.len())));
                }
                for a in &args {
                    face_ref(a, &counts).map_err(|m| err(format!("face vertex `{}`: {m}", shorten(a))))?;
                }
                if keyword == "f" {
                    faces += 1;
                    triangles += args.len() as u64 - 2;
                } else {
                    has_lines = true;
                }
            }
            // Comments, `o`, `g`, `s`, `mtllib`, `usemtl` and statements vbrain has no use for.
            _ => {}
        }
    }
    if faces == 0 {
        return Err(Error::parse(path, None, "no faces (`f` lines): nothing to draw"));
    }
    let vertices: u64 = counts.iter().map(|&c| c as u64).sum();
    let memory = triangles * BYTES_PER_TRIANGLE + vertices * BYTES_PER_VERTEX + bytes.len() as u64;
    crate::input::fits_in_memory(path, memory, &format!("reading its {triangles} triangles"))?;
    // Every line is UTF-8, hence the whole.
    let text = std::str::from_utf8(bytes).map_err(|_| Error::parse(path, None, "not UTF-8 text"))?;
    if !has_lines {
        return Ok(text.into());
    }
    let keep = |line: &str| !matches!(line.split_whitespace().next(), Some("l" | "p"));
    Ok(text.split('\n').map(|l| if keep(l) { l } else { "" }).collect::<Vec<_>>().join("\n").into())
}

fn shorten(s: &str) -> String {
    if s.chars().count() > 40 {
        format!("{}...", s.chars().take(40).collect::<String>())
    } else {
        s.to_string()
    }
}

fn floats(args: &[&str], line: usize, path: &Path) -> Result<Vec<f32>> {
    args.iter()
        .map(|a| match a.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(Error::parse(path, Some(line), format!("number `{}` is not finite", shorten(a)))),
            Err(_) => Err(Error::parse(path, Some(line), format!("`{}` is not a number", shorten(a)))),
        })
        .collect()
}

/// What is wrong with a face reference.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
enum FaceRefError {
    #[error("more than three indices")]
    TooMany,
    #[error("missing vertex index")]
    NoVertex,
    #[error("{0} index is not an integer")]
    NotInteger(&'static str),
    #[error("{0} index 0 (OBJ indices start at 1)")]
    Zero(&'static str),
    #[error("{what} index {index} out of range ({defined} defined so far)")]
    OutOfRange { what: &'static str, index: i64, defined: i64 },
}

/// Checks one face reference `v`, `v/vt`, `v//vn` or `v/vt/vn` against the counts so far.
fn face_ref(r: &str, counts: &[usize; 3]) -> std::result::Result<(), FaceRefError> {
    let parts: Vec<&str> = r.split('/').collect();
    if parts.len() > 3 {
        return Err(FaceRefError::TooMany);
    }
    for (k, p) in parts.iter().enumerate() {
        if p.is_empty() {
            if k == 0 {
                return Err(FaceRefError::NoVertex);
            }
            continue;
        }
        let what = ["vertex", "texture", "normal"][k];
        let i: i64 = p.parse().map_err(|_| FaceRefError::NotInteger(what))?;
        let n = counts[k] as i64;
        let ok = if i > 0 { i <= n } else { i < 0 && -i <= n };
        if !ok {
            return Err(if i == 0 {
                FaceRefError::Zero(what)
            } else {
                FaceRefError::OutOfRange { what, index: i, defined: n }
            });
        }
    }
    Ok(())
}

/// Writes meshes as a VBO file (text as defined above) into `out`.
pub fn write_vbo(objects: &[(&str, &Mesh)], out: &mut dyn std::io::Write) -> std::io::Result<()> {
    writeln!(out, "# Virtual Brain Object (vbrain): o, v, vn, f; millimetres, RAS")?;
    let mut base = 1u64;
    for (name, mesh) in objects {
        writeln!(out, "o {name}")?;
        for p in &mesh.positions {
            writeln!(out, "v {} {} {}", p[0], p[1], p[2])?;
        }
        for n in &mesh.normals {
            writeln!(out, "vn {:.4} {:.4} {:.4}", n[0], n[1], n[2])?;
        }
        for t in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| i as u64 + base);
            writeln!(out, "f {a}//{a} {b}//{b} {c}//{c}")?;
        }
        base += mesh.positions.len() as u64;
    }
    Ok(())
}
