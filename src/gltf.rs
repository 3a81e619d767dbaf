//! glTF 2.0 export (binary `.glb`) of what a scene shows: one mesh per drawn organ (visible, not
//! fully faded), with the set's groups as nested nodes.
//!
//! - Per organ: its name, colour and opacity (as the material's alpha), its transform as its
//!   node's matrix, and its id, Latin name, synonyms, group and info text in the node's `extras`.
//! - Clip planes are applied to the geometry, cut faces included ([`crate::cut_mesh`]); organs
//!   kept whole are not cut.
//! - Meshes stay in organ space (millimetres, RAS); the root node `vbrain` maps RAS millimetres to
//!   glTF's metres with +Y up and +Z to the front: glTF (x, y, z) = (-R, S, A) / 1000, so a viewer
//!   facing the model's front sees its anterior side.
//! - Colours are stored linear, as glTF asks (the set keeps sRGB). Organs take the layout's
//!   colouring ([`crate::colouring`]): by lobe their material's colour; by arterial territory a
//!   white material and each vertex's territory colour (`COLOR_0`, 8-bit RGBA).

use crate::clip::{ClipPlane, Section};
use crate::layout::Layout;
use crate::mesh::Mesh;
use crate::organ_set::OrganSet;
use glam::{Mat4, Vec4};
use serde_json::{json, Value};
use std::borrow::Cow;

/// The matrix of the root node: RAS millimetres to glTF metres, +Y superior, +Z anterior.
pub const ROOT_MATRIX: [f32; 16] =
    [-0.001, 0.0, 0.0, 0.0, 0.0, 0.0, 0.001, 0.0, 0.0, 0.001, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];

/// One organ as exported: its index in the set and its geometry, cut or as it is.
struct Part<'a> {
    organ: usize,
    mesh: Cow<'a, Mesh>,
}

/// A binary glTF file and how many organs it holds.
pub struct Glb {
    pub bytes: Vec<u8>,
    /// Organs exported: drawn, and not wholly cut away.
    pub organs: usize,
}

/// How vertices are stored. Indices are 16-bit wherever an organ has few enough vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// Positions and normals as 32-bit floats: every glTF reader takes it.
    Float,
    /// Normals as 8-bit normalised integers (`KHR_mesh_quantization`, required): a third smaller,
    /// for web pages (three.js reads it).
    CompactNormals,
}

/// The scene as a binary glTF file: the organs `layout` draws, cut by `section`.
pub fn glb(set: &OrganSet, layout: &Layout, section: &Section, encoding: Encoding) -> Glb {
    let parts: Vec<Part> = (0..set.organs.len())
        .filter(|&i| layout.organs[i].is_drawn())
        .filter_map(|i| {
            let organ = &set.organs[i];
            let matrix = layout.organs[i].transform.matrix();
            let planes: Vec<ClipPlane> = if section.whole.contains(&i) {
                Vec::new()
            } else {
                section.planes.iter().filter_map(|p| in_organ_space(p, &matrix)).collect()
            };
            let mesh = match crate::cut_mesh::cut(organ.mesh(), &planes, section.caps && organ.closed()) {
                Some(cut) => Cow::Owned(cut),
                None => Cow::Borrowed(organ.mesh()),
            };
            (!mesh.indices.is_empty()).then_some(Part { organ: i, mesh })
        })
        .collect();
    let (json, bin) = document(set, layout, section, &parts, encoding);
    Glb { bytes: pack(&json, &bin), organs: parts.len() }
}

/// A world-space plane in the space of an organ whose model matrix is `m`: `n · (M q) > d` is
/// `(Mᵀ (n, -d)) · (q, 1) > 0`.
fn in_organ_space(p: &ClipPlane, m: &Mat4) -> Option<ClipPlane> {
    let n = p.normal();
    let q = m.transpose() * Vec4::new(n.x, n.y, n.z, -p.d);
    ClipPlane::new(q.truncate(), -q.w)
}

/// sRGB component to linear.
fn linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// The glTF JSON and its binary buffer.
fn document(
    set: &OrganSet,
    layout: &Layout,
    section: &Section,
    parts: &[Part],
    encoding: Encoding,
) -> (Value, Vec<u8>) {
    let mut bin: Vec<u8> = Vec::new();
    let mut views = Vec::new();
    let mut accessors = Vec::new();
    let mut meshes = Vec::new();
    let mut materials = Vec::new();
    let mut nodes: Vec<Value> = vec![json!({"name": "vbrain", "matrix": ROOT_MATRIX, "children": []})];
    // Group path -> node index; children lists filled as nodes are added.
    let mut groups: Vec<(String, usize)> = Vec::new();
    let mut children: Vec<Vec<usize>> = vec![Vec::new()];
    let colours = crate::colouring::organ_colours(set, layout);
    let territories = set.territories.as_ref().filter(|_| layout.colour_by == crate::layout::ColourBy::Territory);

    let mut view = |bin: &mut Vec<u8>, bytes: &[u8], target: u32, stride: Option<usize>| {
        let offset = bin.len();
        bin.extend_from_slice(bytes);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len(), "target": target});
        if let Some(stride) = stride {
            v["byteStride"] = json!(stride);
        }
        views.push(v);
        views.len() - 1
    };

    for part in parts {
        let organ = &set.organs[part.organ];
        let state = &layout.organs[part.organ];
        let m: &Mesh = &part.mesh;
        let is_cut = matches!(part.mesh, Cow::Owned(_));
        let b = m.bounds();
        let pos = view(&mut bin, bytemuck::cast_slice(&m.positions), 34962, None);
        let normals = match encoding {
            Encoding::Float => {
                let v = view(&mut bin, bytemuck::cast_slice(&m.normals), 34962, None);
                json!({"bufferView": v, "componentType": 5126, "count": m.normals.len(), "type": "VEC3"})
            }
            Encoding::CompactNormals => {
                // Each normal in 4 bytes (x, y, z, padding): vertex attributes keep 4-byte strides.
                let packed: Vec<[i8; 4]> = m.normals.iter().map(|&n| pack_normal(n)).collect();
                let v = view(&mut bin, bytemuck::cast_slice(&packed), 34962, Some(4));
                json!({"bufferView": v, "componentType": 5120, "normalized": true, "count": m.normals.len(), "type": "VEC3"})
            }
        };
        let (idx, index_type) = if m.positions.len() <= usize::from(u16::MAX) {
            let short: Vec<u16> = m.indices.iter().map(|&i| i as u16).collect();
            (view(&mut bin, bytemuck::cast_slice(&short), 34963, None), 5123)
        } else {
            (view(&mut bin, bytemuck::cast_slice(&m.indices), 34963, None), 5125)
        };
        let a = accessors.len();
        accessors.push(json!({"bufferView": pos, "componentType": 5126, "count": m.positions.len(), "type": "VEC3",
            "min": b.min, "max": b.max}));
        accessors.push(normals);
        accessors
            .push(json!({"bufferView": idx, "componentType": index_type, "count": m.indices.len(), "type": "SCALAR"}));
        let mut attributes = json!({"POSITION": a, "NORMAL": a + 1});
        let mut colour = colours.get(part.organ).copied().unwrap_or(state.colour);
        if let Some(tints) = territories.and_then(|t| crate::colouring::territory_colours(t, m)) {
            let rgba: Vec<[u8; 4]> = tints
                .iter()
                .map(|c| {
                    let [r, g, b] =
                        c.unwrap_or(crate::colouring::UNSUPPLIED).map(|v| (linear(v) * 255.0).round() as u8);
                    [r, g, b, 255]
                })
                .collect();
            let v = view(&mut bin, bytemuck::cast_slice(&rgba), 34962, Some(4));
            attributes["COLOR_0"] = json!(accessors.len());
            accessors.push(json!({"bufferView": v, "componentType": 5121, "normalized": true, "count": rgba.len(), "type": "VEC4"}));
            colour = [1.0; 3];
        }
        let [r, g, bl] = colour.map(linear);
        let opacity = state.opacity.clamp(0.0, 1.0);
        let mut material = json!({"name": organ.name, "doubleSided": !organ.closed() || (is_cut && !section.caps),
            "pbrMetallicRoughness": {"baseColorFactor": [r, g, bl, opacity], "metallicFactor": 0.0, "roughnessFactor": 0.6}});
        if opacity < 1.0 {
            material["alphaMode"] = json!("BLEND");
        }
        materials.push(material);
        meshes.push(json!({"name": organ.name, "primitives": [{"attributes": attributes,
            "indices": a + 2, "material": materials.len() - 1, "mode": 4}]}));
        let mut extras = json!({"id": organ.id, "group": organ.group, "info": organ.info, "opacity": opacity});
        if let Some(latin) = &organ.latin {
            extras["latin"] = json!(latin);
        }
        if !organ.synonyms.is_empty() {
            extras["synonyms"] = json!(organ.synonyms);
        }
        let matrix = state.transform.matrix();
        let mut node = json!({"name": organ.name, "mesh": meshes.len() - 1, "extras": extras});
        if matrix != Mat4::IDENTITY {
            node["matrix"] = json!(matrix.to_cols_array());
        }
        // The organ's group nodes, made as first needed.
        let mut parent = 0;
        let mut path = String::new();
        for name in organ.group.split('/').filter(|s| !s.is_empty()) {
            if !path.is_empty() {
                path.push('/');
            }
            path.push_str(name);
            parent = match groups.iter().find(|(p, _)| *p == path) {
                Some(&(_, n)) => n,
                None => {
                    nodes.push(json!({"name": name, "extras": {"group": path}}));
                    children.push(Vec::new());
                    let n = nodes.len() - 1;
                    children[parent].push(n);
                    groups.push((path.clone(), n));
                    n
                }
            };
        }
        nodes.push(node);
        children.push(Vec::new());
        children[parent].push(nodes.len() - 1);
    }
    for (node, kids) in nodes.iter_mut().zip(&children) {
        if !kids.is_empty() {
            node["children"] = json!(kids);
        } else if let Some(o) = node.as_object_mut() {
            o.remove("children");
        }
    }
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": concat!("vbrain ", env!("CARGO_PKG_VERSION"))},
        "scene": 0,
        "scenes": [{"name": set.title, "nodes": [0]}],
        "nodes": nodes,
    });
    if encoding == Encoding::CompactNormals {
        doc["extensionsUsed"] = json!(["KHR_mesh_quantization"]);
        doc["extensionsRequired"] = json!(["KHR_mesh_quantization"]);
    }
    if !meshes.is_empty() {
        doc["meshes"] = json!(meshes);
        doc["materials"] = json!(materials);
        doc["accessors"] = json!(accessors);
        doc["bufferViews"] = json!(views);
        doc["buffers"] = json!([{"byteLength": bin.len()}]);
    }
    (doc, bin)
}

/// The GLB container: a 12-byte header, the JSON chunk (padded with spaces) and the binary chunk
/// (padded with zeros), each chunk 4-byte aligned.
fn pack(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut text = json.to_string().into_bytes();
    while !text.len().is_multiple_of(4) {
        text.push(b' ');
    }
    let mut out = Vec::with_capacity(28 + text.len() + bin.len());
    let total = 12 + 8 + text.len() + if bin.is_empty() { 0 } else { 8 + bin.len() };
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&text);
    if !bin.is_empty() {
        out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
        out.extend_from_slice(b"BIN\0");
        out.extend_from_slice(bin);
    }
    out
}

/// A unit normal as four signed bytes (x, y, z, 0), read back as `byte / 127`. Rounding each
/// component alone can leave the vector up to 0.7 % off unit length, more than glTF validators
/// accept; of the 27 roundings up or down around it, the one that keeps nearest to unit length
/// within 0.5 % and then nearest in direction is chosen.
fn pack_normal(n: [f32; 3]) -> [i8; 4] {
    let n = glam::Vec3::from(n).normalize_or_zero() * 127.0;
    let base = n.floor();
    let mut best = (f32::MAX, [0i8; 4]);
    for i in 0..27 {
        let step = glam::Vec3::new((i % 3) as f32, (i / 3 % 3) as f32, (i / 9) as f32) - 1.0;
        let q =
            (base + step + glam::Vec3::splat(0.5)).floor().clamp(glam::Vec3::splat(-127.0), glam::Vec3::splat(127.0));
        let off_unit = (q.length() / 127.0 - 1.0).abs();
        let off_direction = (q - n).length() / 127.0;
        let score = if off_unit < 0.005 { off_direction } else { 1.0 + off_unit };
        if score < best.0 {
            best = (score, [q.x as i8, q.y as i8, q.z as i8, 0]);
        }
    }
    best.1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::organ_set::Organ;
    use glam::Vec3;

    fn set() -> OrganSet {
        let mut set = OrganSet { title: "t".into(), ..Default::default() };
        let mut a = Organ::new("a".into(), "<A & b>".into(), [1.0, 0.5, 0.0], Mesh::octahedron());
        a.group = "Left/Lobe".into();
        a.info = "Text".into();
        set.organs.push(a);
        set.organs.push(Organ::new("b".into(), "B".into(), [0.0; 3], Mesh::octahedron()));
        set
    }

    /// The JSON chunk of a GLB.
    fn json_of(glb: &[u8]) -> Value {
        assert_eq!(&glb[0..4], b"glTF");
        assert_eq!(u32::from_le_bytes(glb[8..12].try_into().unwrap()) as usize, glb.len());
        let len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        assert_eq!(len % 4, 0);
        serde_json::from_slice(&glb[20..20 + len]).unwrap()
    }

    #[test]
    fn packed_normals_keep_unit_length() {
        let mut rng = crate::rng::XorShift::seeded(7);
        for _ in 0..20_000 {
            let n = glam::Vec3::new(rng.unit() - 0.5, rng.unit() - 0.5, rng.unit() - 0.5).normalize();
            let q = pack_normal(n.into());
            let back = glam::Vec3::new(q[0] as f32, q[1] as f32, q[2] as f32) / 127.0;
            assert!((back.length() - 1.0).abs() < 0.005, "{n} -> {back}");
            assert!(back.normalize().dot(n) > 0.9995, "{n} -> {back}");
        }
        assert_eq!(pack_normal([0.0, 0.0, -1.0]), [0, 0, -127, 0]);
    }

    #[test]
    fn organs_groups_and_materials() {
        let set = set();
        let mut layout = Layout::new(&set);
        layout.organs[0].opacity = 0.4;
        let doc = json_of(&glb(&set, &layout, &Section::default(), Encoding::Float).bytes);
        let nodes = doc["nodes"].as_array().unwrap();
        let names: Vec<&str> = nodes.iter().map(|n| n["name"].as_str().unwrap()).collect();
        assert_eq!(names, ["vbrain", "Left", "Lobe", "<A & b>", "B"]);
        assert_eq!(nodes[0]["children"], json!([1, 4]));
        assert_eq!(nodes[2]["children"], json!([3]));
        assert_eq!(nodes[3]["extras"]["id"], "a");
        let m = &doc["materials"][0];
        assert_eq!(m["alphaMode"], "BLEND");
        assert!((m["pbrMetallicRoughness"]["baseColorFactor"][1].as_f64().unwrap() - 0.214).abs() < 1e-3);
        assert!(doc["materials"][1].get("alphaMode").is_none());
        // Hidden organs are left out.
        layout.organs[1].visible = false;
        let doc = json_of(&glb(&set, &layout, &Section::default(), Encoding::Float).bytes);
        assert_eq!(doc["meshes"].as_array().unwrap().len(), 1);
    }

    #[test]
    fn a_cut_is_in_the_geometry_and_follows_a_moved_organ() {
        let set = set();
        let mut layout = Layout::new(&set);
        let section = Section {
            planes: vec![ClipPlane::new(Vec3::Z, 0.0).unwrap()],
            caps: true,
            whole: vec![1],
            ..Default::default()
        };
        // Organ a moved 10 mm up: the plane z = 0 lies below it, nothing of it is cut.
        layout.organs[0].transform.translation = Vec3::new(0.0, 0.0, 10.0);
        let doc = json_of(&glb(&set, &layout, &section, Encoding::Float).bytes);
        assert_eq!(doc["accessors"][0]["min"][2], json!(-1.0));
        layout.organs[0].transform.translation = Vec3::ZERO;
        let doc = json_of(&glb(&set, &layout, &section, Encoding::Float).bytes);
        assert_eq!(doc["accessors"][0]["max"][2], json!(0.0), "a is cut at z = 0");
        assert_eq!(doc["accessors"][3]["max"][2], json!(1.0), "b is kept whole");
    }
}
