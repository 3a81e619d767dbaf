//! Reading one NIfTI-1 file (`.nii` or `.nii.gz`), for label volumes and MRI alike: the one place a
//! NIfTI input is opened and checked, before any voxel is read.
//!
//! - Only the file given is opened: a header-only `.nii` (magic `ni1`, data in a `.img` beside it)
//!   is refused, never followed.
//! - The header is checked first (rank, dimensions, voxel count against the caller's bound, the
//!   data type, the offset of the voxels), naming the field, so a header claiming a huge volume or
//!   huge extensions is refused before anything is allocated.
//! - Values are the stored numbers scaled by `scl_slope`/`scl_inter` where the slope is set.
//! - The affine maps voxel indices (x fastest) to world space, millimetres RAS for atlases and
//!   scanners: sform if set, else qform, else the pixel sizes.

use crate::error::{Error, Result};
use glam::{Mat4, Vec3, Vec4};
use std::io::Read;
use std::path::Path;

/// The most bytes of extensions before the voxels (the header's `vox_offset` less 352).
pub const MAX_EXTENSION_BYTES: u64 = 16 << 20;

/// The voxels of a NIfTI file as stored, with what is needed to read them.
pub struct RawVolume {
    pub dims: [usize; 3],
    pub affine: Mat4,
    ty: nifti::NiftiType,
    size: usize,
    big_endian: bool,
    raw: Vec<u8>,
    /// `scl_slope`, `scl_inter` (slope 1, inter 0 where the header sets none).
    scale: (f64, f64),
}

impl RawVolume {
    pub fn len(&self) -> usize {
        self.dims[0] * self.dims[1] * self.dims[2]
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Is the stored type a floating-point one?
    pub fn is_float(&self) -> bool {
        matches!(self.ty, nifti::NiftiType::Float32 | nifti::NiftiType::Float64)
    }

    /// Voxel `i` (x fastest), scaled.
    pub fn value(&self, i: usize) -> f64 {
        use nifti::NiftiType as T;
        let mut b = [0u8; 8];
        b[..self.size].copy_from_slice(&self.raw[i * self.size..(i + 1) * self.size]);
        if self.big_endian {
            b[..self.size].reverse();
        }
        let v = match self.ty {
            T::Uint8 => b[0] as f64,
            T::Int8 => b[0] as i8 as f64,
            T::Int16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            T::Uint16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            T::Int32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            T::Uint32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            T::Float32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            T::Int64 => i64::from_le_bytes(b) as f64,
            T::Uint64 => u64::from_le_bytes(b) as f64,
            _ => f64::from_le_bytes(b),
        };
        let (slope, inter) = self.scale;
        v * slope + inter
    }
}

/// Reads the 3-D NIfTI file at `path` (a `what`, e.g. "label volume", for messages) of at most
/// `max_voxels` voxels.
pub fn read(path: &Path, what: &str, max_voxels: usize) -> Result<RawVolume> {
    use nifti::NiftiType as T;
    let bad = |m: String| Error::parse(path, None, m);
    crate::input::check_file(path, crate::input::Kind::Volume)?;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut source = std::io::BufReader::new(file);
    let mut magic = [0u8; 2];
    let gz = {
        use std::io::BufRead;
        let head = source.fill_buf().map_err(|e| Error::io(path, e))?;
        magic.iter_mut().zip(head).for_each(|(m, h)| *m = *h);
        magic == [0x1f, 0x8b]
    };
    let mut source: Box<dyn Read> =
        if gz { Box::new(flate2::bufread::GzDecoder::new(source)) } else { Box::new(source) };
    let h = nifti::NiftiHeader::from_reader(&mut source)
        .map_err(|e| bad(format!("not a readable NIfTI header: {}", message(&e))))?;
    if &h.magic == b"ni1\0" {
        return Err(bad("header field magic: a header-only NIfTI file (its voxels in a separate .img) is not read; \
             save it as one .nii or .nii.gz"
            .into()));
    }
    let rank = h.dim[0] as usize;
    if !(3..=4).contains(&rank) || (rank == 4 && h.dim[4] > 1) {
        let dims = &h.dim[1..=rank.clamp(1, 7)];
        return Err(bad(format!("header field dim: expected a 3-D {what}, found {rank} dimensions {dims:?}")));
    }
    if let Some(axis) = (1..=3).find(|&a| h.dim[a] == 0) {
        return Err(bad(format!("header field dim[{axis}] is 0: the volume has no voxels")));
    }
    let dims = [h.dim[1] as usize, h.dim[2] as usize, h.dim[3] as usize];
    let count = dims[0] * dims[1] * dims[2];
    if count > max_voxels {
        return Err(bad(format!(
            "header field dim: {}x{}x{} voxels is more than vbrain reads in a {what} ({max_voxels})",
            dims[0], dims[1], dims[2]
        )));
    }
    let ty = h.data_type().map_err(|e| bad(format!("header field datatype: {}", message(&e))))?;
    let size = match ty {
        T::Uint8 | T::Int8 => 1,
        T::Int16 | T::Uint16 => 2,
        T::Int32 | T::Uint32 | T::Float32 => 4,
        T::Int64 | T::Uint64 | T::Float64 => 8,
        other => return Err(bad(format!("header field datatype: voxel type {other:?} is not read"))),
    };
    let offset = h.vox_offset;
    if !(offset.is_finite() && offset >= 348.0 && (offset as u64).saturating_sub(348) <= MAX_EXTENSION_BYTES) {
        return Err(bad(format!(
            "header field vox_offset: {offset} is not where a single-file NIfTI's voxels can start \
             (348 to {} bytes)",
            348 + MAX_EXTENSION_BYTES
        )));
    }
    // Skip the extensions (the header reader has read 348 bytes).
    let skip = offset as u64 - 348;
    let skipped = std::io::copy(&mut (&mut source).take(skip), &mut std::io::sink()).map_err(|e| Error::io(path, e))?;
    let bytes = count * size;
    let mut raw = Vec::new();
    raw.try_reserve_exact(bytes).map_err(|_| bad(format!("{bytes} bytes of voxels do not fit in memory")))?;
    source.take(bytes as u64).read_to_end(&mut raw).map_err(|e| Error::io(path, e))?;
    if skipped < skip || raw.len() < bytes {
        return Err(bad(format!(
            "the file ends before its voxel data does: {count} voxels of {size} bytes need {bytes}, found {}",
            raw.len()
        )));
    }
    let affine =
        affine_of(&h).ok_or_else(|| bad("no usable voxel-to-world transform (sform, qform or pixel sizes)".into()))?;
    let (slope, inter) = (h.scl_slope as f64, h.scl_inter as f64);
    let scale = if slope != 0.0 && slope.is_finite() && inter.is_finite() { (slope, inter) } else { (1.0, 0.0) };
    Ok(RawVolume { dims, affine, ty, size, big_endian: h.endianness == nifti::Endianness::Big, raw, scale })
}

/// A NIfTI reader's error in words (its I/O errors have no message of their own).
fn message(e: &nifti::NiftiError) -> String {
    match e {
        nifti::NiftiError::Io(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            "the file ends before its header or voxel data do".into()
        }
        nifti::NiftiError::Io(io) => io.to_string(),
        nifti::NiftiError::UnsupportedDataType(t) => format!("header field datatype: {t:?} is not supported"),
        other => other.to_string(),
    }
}

/// The voxel-to-world affine of a header: sform if set, else qform, else the pixel sizes.
fn affine_of(h: &nifti::NiftiHeader) -> Option<Mat4> {
    let m = if h.sform_code > 0 {
        let r = [h.srow_x, h.srow_y, h.srow_z];
        Mat4::from_cols(
            Vec4::new(r[0][0], r[1][0], r[2][0], 0.0),
            Vec4::new(r[0][1], r[1][1], r[2][1], 0.0),
            Vec4::new(r[0][2], r[1][2], r[2][2], 0.0),
            Vec4::new(r[0][3], r[1][3], r[2][3], 1.0),
        )
    } else {
        let (b, c, d) = (h.quatern_b, h.quatern_c, h.quatern_d);
        let a = (1.0 - (b * b + c * c + d * d)).max(0.0).sqrt();
        let q = glam::Quat::from_xyzw(b, c, d, a);
        let qfac = if h.pixdim[0] < 0.0 { -1.0 } else { 1.0 };
        let scale = Vec3::new(h.pixdim[1].abs(), h.pixdim[2].abs(), h.pixdim[3].abs() * qfac);
        let scale = Vec3::select(scale.abs().cmpgt(Vec3::ZERO), scale, Vec3::ONE);
        let rot = if h.qform_code > 0 && q.is_finite() { q.normalize() } else { glam::Quat::IDENTITY };
        let offset = if h.qform_code > 0 { Vec3::new(h.quatern_x, h.quatern_y, h.quatern_z) } else { Vec3::ZERO };
        Mat4::from_translation(offset) * Mat4::from_quat(rot) * Mat4::from_scale(scale)
    };
    (m.is_finite() && m.determinant().abs() > 1e-12).then_some(m)
}

/// A NIfTI-1 file's bytes for tests: `dims`, datatype code and bits, `data` as stored, a 2 mm
/// grid at sform (-10, -10, -10) mm, with the header fields the reader checks.
#[cfg(test)]
pub(crate) struct TestFile<'a> {
    pub dims: [i16; 3],
    pub datatype: (i16, i16),
    pub data: &'a [u8],
    pub slope: f32,
    pub magic: &'a [u8; 4],
    pub vox_offset: f32,
}

#[cfg(test)]
impl TestFile<'_> {
    pub(crate) fn float32(dims: [i16; 3], values: &[f32]) -> Vec<u8> {
        let data: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        TestFile { dims, datatype: (16, 32), data: &data, slope: 0.0, magic: b"n+1\0", vox_offset: 352.0 }.bytes()
    }

    pub(crate) fn bytes(&self) -> Vec<u8> {
        let mut h = vec![0u8; 352];
        let mut put = |at: usize, bytes: &[u8]| h[at..at + bytes.len()].copy_from_slice(bytes);
        put(0, &348i32.to_le_bytes());
        let dim = [3, self.dims[0], self.dims[1], self.dims[2], 1, 1, 1, 1];
        dim.iter().enumerate().for_each(|(i, d)| put(40 + 2 * i, &d.to_le_bytes()));
        put(70, &self.datatype.0.to_le_bytes());
        put(72, &self.datatype.1.to_le_bytes());
        [1.0f32, 2.0, 2.0, 2.0].iter().enumerate().for_each(|(i, p)| put(76 + 4 * i, &p.to_le_bytes()));
        put(108, &self.vox_offset.to_le_bytes());
        put(112, &self.slope.to_le_bytes());
        put(254, &1i16.to_le_bytes());
        let rows = [[2.0f32, 0.0, 0.0, -10.0], [0.0, 2.0, 0.0, -10.0], [0.0, 0.0, 2.0, -10.0]];
        for (r, row) in rows.iter().enumerate() {
            row.iter().enumerate().for_each(|(c, v)| put(280 + 16 * r + 4 * c, &v.to_le_bytes()));
        }
        put(344, self.magic);
        h.resize((self.vox_offset.max(352.0) as usize).min(1 << 20), 0);
        h.extend_from_slice(self.data);
        h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(bytes: &[u8], name: &str) -> (tempfile::TempDir, std::path::PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).unwrap();
        (dir, path)
    }

    #[test]
    fn values_are_scaled_by_the_slope() {
        let data = [1u8, 2, 3, 4, 5, 6, 7, 8];
        let bytes =
            TestFile { dims: [2, 2, 2], datatype: (2, 8), data: &data, slope: 0.5, magic: b"n+1\0", vox_offset: 352.0 }
                .bytes();
        let (_d, path) = file(&bytes, "v.nii");
        let v = read(&path, "volume", 100).unwrap();
        assert_eq!(v.dims, [2, 2, 2]);
        assert_eq!((v.value(0), v.value(7)), (0.5, 4.0));
        assert_eq!(v.affine.transform_point3(glam::Vec3::ONE), glam::Vec3::splat(-8.0));
    }

    #[test]
    fn gzip_is_read_too() {
        use std::io::Write;
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(&TestFile::float32([1, 1, 2], &[1.5, -2.0])).unwrap();
        let (_d, path) = file(&gz.finish().unwrap(), "v.nii.gz");
        let v = read(&path, "volume", 100).unwrap();
        assert_eq!((v.value(0), v.value(1)), (1.5, -2.0));
    }

    #[test]
    fn a_header_only_file_is_refused_not_followed() {
        let bytes =
            TestFile { dims: [1, 1, 1], datatype: (2, 8), data: &[], slope: 0.0, magic: b"ni1\0", vox_offset: 0.0 }
                .bytes();
        let (dir, path) = file(&bytes, "v.nii");
        std::fs::write(dir.path().join("v.img"), [7u8]).unwrap();
        let e = read(&path, "volume", 100).err().unwrap().to_string();
        assert!(e.contains("v.nii") && e.contains("header-only"), "{e}");
    }

    #[test]
    fn bounds_are_checked_before_reading() {
        let (_d, path) = file(&TestFile::float32([10, 10, 10], &[0.0; 8]), "big.nii");
        let e = read(&path, "MRI volume", 100).err().unwrap().to_string();
        assert!(e.contains("dim") && e.contains("more than"), "{e}");
        let huge =
            TestFile { dims: [1, 1, 1], datatype: (2, 8), data: &[1], slope: 0.0, magic: b"n+1\0", vox_offset: 4e9 };
        let (_d, path) = file(&huge.bytes(), "ext.nii");
        let e = read(&path, "volume", 100).err().unwrap().to_string();
        assert!(e.contains("vox_offset"), "{e}");
        let (_d, path) = file(&TestFile::float32([2, 2, 2], &[0.0; 3]), "short.nii");
        let e = read(&path, "volume", 100).err().unwrap().to_string();
        assert!(e.contains("ends before"), "{e}");
    }
}
