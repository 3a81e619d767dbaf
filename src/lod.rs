//! Level of detail (Callahan 2005, chapter 5): per organ a chain of simplified versions of its
//! mesh, built offline with meshopt and stored beside the set, drawn while the view moves.
//!
//! - A level is a list of triangles: indices into the organ's own vertices as loaded. meshopt's
//!   simplification only takes vertices away (it never moves or adds one), so a level draws with
//!   the organ's vertex data, and lies inside the organ's bounds.
//! - Each level has about a quarter of the triangles of the one before ([`RATIOS`]); the mesh's
//!   borders are locked, and a closed organ's chain stops before a level that would open it.
//! - Stored as `meshes/ID.lod` (gzip of little-endian u32s: [`MAGIC`], the organ's vertex count,
//!   the number of levels, then per level its index count and indices) and named by the
//!   manifest's `lod`. A file written for other vertices (the mesh was changed since) is refused.

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use std::io::{Read, Write};
use std::path::Path;

/// Each level's share of the organ's triangles.
pub const RATIOS: [f32; 2] = [0.25, 0.0625];

/// The most a level may depart from the organ's surface, as a share of the mesh's extent
/// (meshopt's relative error): a level stops short of its triangle count where it would go further.
pub const MAX_ERROR: f32 = 0.02;

/// Organs with fewer triangles get no levels: they cost little to draw whole.
pub const MIN_TRIANGLES: usize = 512;

/// The first word of a level file ("VLOD" read as little-endian bytes).
pub const MAGIC: u32 = u32::from_le_bytes(*b"VLOD");

/// The levels of `mesh`, coarsest last (none for a small mesh); `closed` organs keep only levels
/// that are closed too.
pub fn levels(mesh: &Mesh, closed: bool) -> Vec<Vec<u32>> {
    let triangles = mesh.triangle_count();
    if triangles < MIN_TRIANGLES {
        return Vec::new();
    }
    let bytes: &[u8] = bytemuck::cast_slice(&mesh.positions);
    let Ok(adapter) = meshopt::VertexDataAdapter::new(bytes, 12, 0) else { return Vec::new() };
    let mut out: Vec<Vec<u32>> = Vec::new();
    for ratio in RATIOS {
        let source = out.last().unwrap_or(&mesh.indices);
        let target = ((triangles as f32 * ratio) as usize).max(4) * 3;
        let level = meshopt::simplify(source, &adapter, target, MAX_ERROR, meshopt::SimplifyOptions::LockBorder, None);
        // A level that saves little, or opens a closed organ, ends the chain.
        let opened = closed && {
            let m = Mesh { positions: mesh.positions.clone(), normals: Vec::new(), indices: level.clone() };
            m.open_edges() > 0
        };
        if level.len() < 12 || level.len() as f32 > source.len() as f32 * 0.6 || opened {
            break;
        }
        out.push(level);
    }
    out
}

/// Writes `levels` of an organ with `vertices` vertices in the file format above.
pub fn write(levels: &[Vec<u32>], vertices: usize, out: &mut dyn Write) -> std::io::Result<()> {
    let mut gz = flate2::write::GzEncoder::new(out, flate2::Compression::default());
    let mut words = vec![MAGIC, vertices as u32, levels.len() as u32];
    for level in levels {
        words.push(level.len() as u32);
        words.extend_from_slice(level);
    }
    gz.write_all(bytemuck::cast_slice(&words))?;
    gz.finish()?;
    Ok(())
}

/// Reads the levels of an organ with `vertices` vertices and `indices` indices from `path`: at most
/// [`RATIOS`]`.len()` levels, each of whole triangles, fewer than the organ's, and naming only its
/// vertices.
pub fn read(path: &Path, vertices: usize, indices: usize) -> Result<Vec<Vec<u32>>> {
    let bad = |m: String| Error::parse(path, None, m);
    let bytes = crate::input::read(path, crate::input::Kind::Mesh)?;
    // The most a valid file holds: the header, then each level's count and indices.
    let most = (3 + RATIOS.len() * (1 + indices)) * 4;
    let mut raw = Vec::new();
    flate2::read::GzDecoder::new(bytes.as_slice())
        .take(most as u64 + 1)
        .read_to_end(&mut raw)
        .map_err(|e| bad(format!("not a level file (gzip): {e}")))?;
    if raw.len() > most || !raw.len().is_multiple_of(4) {
        return Err(bad(format!("{} bytes is not a level file of an organ with {indices} indices", raw.len())));
    }
    let words: Vec<u32> = raw.chunks_exact(4).map(|w| u32::from_le_bytes([w[0], w[1], w[2], w[3]])).collect();
    let (header, mut rest) = words.split_at(3.min(words.len()));
    match header {
        [MAGIC, v, n] if *v as usize == vertices && *n as usize <= RATIOS.len() => {
            let mut levels = Vec::with_capacity(*n as usize);
            for k in 0..*n as usize {
                let Some((&count, after)) = rest.split_first() else {
                    return Err(bad(format!("level {} is cut short", k + 1)));
                };
                let count = count as usize;
                if count > after.len() || !count.is_multiple_of(3) || count >= indices {
                    return Err(bad(format!("level {}: {count} indices is not a level of {indices}", k + 1)));
                }
                let (level, next) = after.split_at(count);
                if let Some(i) = level.iter().find(|&&i| i as usize >= vertices) {
                    return Err(bad(format!("level {}: vertex {i} of {vertices}", k + 1)));
                }
                levels.push(level.to_vec());
                rest = next;
            }
            Ok(levels)
        }
        [MAGIC, v, _] if *v as usize != vertices => Err(bad(format!(
            "written for a mesh of {v} vertices, and the organ's has {vertices}: run `vbrain lod` on the set again"
        ))),
        _ => Err(bad("not a level file of vbrain (its header)".into())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chain_shrinks_stays_closed_and_reads_back() {
        let mesh = Mesh::uv_sphere(10.0, 32, 64);
        assert!(mesh.is_closed_outward());
        let levels = levels(&mesh, true);
        assert_eq!(levels.len(), 2, "two levels of a sphere of {} triangles", mesh.triangle_count());
        let mut before = mesh.indices.len();
        for level in &levels {
            assert!(level.len() * 2 < before, "{} indices after {before}", level.len());
            let m = Mesh { positions: mesh.positions.clone(), normals: vec![], indices: level.clone() };
            assert!(m.is_closed_outward(), "a level of a closed mesh is closed and wound outward");
            before = level.len();
        }
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.lod");
        let mut bytes = Vec::new();
        write(&levels, mesh.positions.len(), &mut bytes).unwrap();
        std::fs::write(&path, &bytes).unwrap();
        assert_eq!(read(&path, mesh.positions.len(), mesh.indices.len()).unwrap(), levels);
        // Written for other vertices: stale, and said so.
        let e = read(&path, mesh.positions.len() + 1, mesh.indices.len()).unwrap_err().to_string();
        assert!(e.contains("s.lod") && e.contains("vbrain lod"), "{e}");
        std::fs::write(&path, b"not gzip").unwrap();
        assert!(read(&path, mesh.positions.len(), mesh.indices.len()).is_err());
    }

    #[test]
    fn a_small_mesh_gets_no_levels() {
        let mesh = Mesh::uv_sphere(10.0, 8, 8);
        assert!(mesh.triangle_count() < MIN_TRIANGLES);
        assert!(levels(&mesh, true).is_empty());
    }
}
