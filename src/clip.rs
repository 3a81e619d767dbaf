//! Clip planes (issue: cross-sections): each removes the points `p` of world space (millimetres,
//! RAS) where `n · p > d`. The anatomical planes are named by the side they cut away: `axial`
//! removes what lies superior of z = mm, `coronal` what lies anterior of y = mm, `sagittal` what
//! lies right of x = mm; `:flip` keeps that side instead. At most [`MAX_PLANES`] at once; an organ
//! marked "do not cut" is never clipped. Normals are stored unit length.
//! - [`Section`] is the one value of a cross-section: planes, cut faces, organs kept whole (the
//!   viewer, the renderer's [`crate::render::FrameInput`] and the culler take it); files keep it as a
//!   [`SavedSection`] (organs by id or group).
//! - [`Section::organ`] classifies one organ against it ([`OrganClip`]): the renderer draws by that
//!   classification and the culler reasons from the same one, so culling stays conservative.

use crate::mesh::Bounds;
use glam::Vec3;
use serde::{Deserialize, Serialize};

/// Planes at once (the shaders' uniform array).
pub const MAX_PLANES: usize = 4;

/// The farthest a plane may lie from the origin, millimetres (10 m: far past any organ set).
pub const MAX_OFFSET_MM: f32 = 10_000.0;

#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "PlaneFields")]
pub struct ClipPlane {
    /// Unit normal, pointing into the removed side.
    pub normal: [f32; 3],
    /// Millimetres along the normal from the origin.
    pub d: f32,
}

/// A cross-section: the planes (world space; the first [`MAX_PLANES`] apply), whether closed
/// organs they cut show solid cut faces and what those faces show, and the organs (indices,
/// sorted) the planes never cut.
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    pub planes: Vec<ClipPlane>,
    pub caps: bool,
    pub faces: CutFace,
    pub whole: Vec<usize>,
}

/// No planes, cut faces on, in the organs' colours.
pub static NO_SECTION: Section = Section { planes: Vec::new(), caps: true, faces: CutFace::COLOUR, whole: Vec::new() };

/// What solid cut faces show: the organ's colour, the set's MRI (through a window), or the MRI
/// tinted by the organ's colour. A set without an MRI shows colours whatever this says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CutFace {
    #[serde(default)]
    pub show: CutFaceShows,
    #[serde(default)]
    pub window: crate::mri::Window,
}

impl CutFace {
    /// The organs' colours with the default window (what files leave out).
    pub fn is_default(&self) -> bool {
        *self == CutFace::default()
    }

    pub const COLOUR: CutFace =
        CutFace { show: CutFaceShows::Colour, window: crate::mri::Window { window: 0.9, level: 0.6 } };
}

#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CutFaceShows {
    #[default]
    Colour,
    Mri,
    Tinted,
}

impl CutFaceShows {
    pub const ALL: [CutFaceShows; 3] = [CutFaceShows::Colour, CutFaceShows::Mri, CutFaceShows::Tinted];

    /// The name on the command line and in files.
    pub fn name(self) -> &'static str {
        match self {
            CutFaceShows::Colour => "colour",
            CutFaceShows::Mri => "mri",
            CutFaceShows::Tinted => "tinted",
        }
    }

    /// The name in the viewer.
    pub fn label(self) -> &'static str {
        match self {
            CutFaceShows::Colour => "Organ colour",
            CutFaceShows::Mri => "MRI",
            CutFaceShows::Tinted => "MRI tinted by organ",
        }
    }
}

impl Default for Section {
    fn default() -> Self {
        NO_SECTION.clone()
    }
}

/// How a section treats one organ, as the renderer draws it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OrganClip {
    /// The planes apply to it: there are some, and it is not kept whole.
    pub clipped: bool,
    /// Where its bounds lie against the planes ([`Side::Kept`] where not clipped).
    pub side: Side,
    /// Drawn with solid cut faces: clipped, cut by the planes, closed, and cut faces on.
    pub capped: bool,
}

impl Section {
    /// The planes that apply (the first [`MAX_PLANES`]).
    pub fn active_planes(&self) -> &[ClipPlane] {
        &self.planes[..self.planes.len().min(MAX_PLANES)]
    }

    /// Whether the planes apply to organ `o` (they may still miss it).
    pub fn applies_to(&self, o: usize) -> bool {
        !self.planes.is_empty() && !self.whole.contains(&o)
    }

    /// How the section treats organ `o`, whose mesh has `bounds` in world space and is `closed`.
    pub fn organ(&self, o: usize, bounds: &Bounds, closed: bool) -> OrganClip {
        if !self.applies_to(o) {
            return OrganClip { clipped: false, side: Side::Kept, capped: false };
        }
        let side = side(self.active_planes(), bounds);
        OrganClip { clipped: true, side, capped: self.caps && closed && side == Side::Cut }
    }

    /// Whether organ `o`, with `bounds` in world space, lies inside every plane by `share` of its
    /// far corner's distance from `eye` (or the planes do not apply to it): then no plane changes
    /// any sample of it, however interpolated.
    pub fn clear_of(&self, o: usize, bounds: &Bounds, eye: Vec3, share: f32) -> bool {
        if !self.applies_to(o) {
            return true;
        }
        let far = bounds.corners().iter().map(|&c| (c - eye).length()).fold(0.0, f32::max);
        side_within(&self.planes, bounds, share * far) == Side::Kept
    }
}

/// A section as scene files and lesson steps keep it: organs kept whole by id or group.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SavedSection {
    pub planes: Vec<ClipPlane>,
    pub caps: bool,
    pub faces: CutFace,
    pub whole: Vec<String>,
}

impl SavedSection {
    /// `section` as saved for `set`: its whole organs by id.
    pub fn of(section: &Section, set: &crate::organ_set::OrganSet) -> SavedSection {
        SavedSection {
            planes: section.planes.clone(),
            caps: section.caps,
            faces: section.faces,
            whole: set.ids(&section.whole),
        }
    }

    /// The section in `set`, and the names of `whole` that name no organ or group there.
    pub fn resolve(&self, set: &crate::organ_set::OrganSet) -> (Section, Vec<String>) {
        let (whole, unknown) = crate::labels::Which::chosen(&self.whole, set);
        (Section { planes: self.planes.clone(), caps: self.caps, faces: self.faces, whole }, unknown)
    }
}

/// Where a box lies against the planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Wholly kept by every plane.
    Kept,
    /// Wholly removed by some plane.
    Removed,
    /// Some plane passes through it.
    Cut,
}

/// A plane as files hold it, checked by [`ClipPlane::new`] as it is read.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlaneFields {
    normal: [f32; 3],
    d: f32,
}

impl TryFrom<PlaneFields> for ClipPlane {
    type Error = String;
    fn try_from(f: PlaneFields) -> Result<ClipPlane, String> {
        ClipPlane::new(Vec3::from(f.normal), f.d).ok_or_else(|| {
            format!(
                "clip plane normal {:?}, d {}: a plane needs a non-zero normal and lies within {MAX_OFFSET_MM} mm \
                 of the origin",
                f.normal, f.d
            )
        })
    }
}

/// Why `planes` cannot be one section: more than [`MAX_PLANES`].
pub fn planes_problem(planes: &[ClipPlane]) -> Option<String> {
    (planes.len() > MAX_PLANES).then(|| format!("{} clip planes: a section has at most {MAX_PLANES}", planes.len()))
}

impl ClipPlane {
    /// A plane removing `n · p > d`; `None` for a zero or non-finite normal or offset, or one
    /// farther than [`MAX_OFFSET_MM`] from the origin.
    pub fn new(normal: Vec3, d: f32) -> Option<ClipPlane> {
        let len = normal.length();
        if !(len.is_finite() && len > 1e-6 && d.is_finite() && (d / len).abs() <= MAX_OFFSET_MM) {
            return None;
        }
        Some(ClipPlane { normal: (normal / len).to_array(), d: d / len })
    }

    /// Parses `axial=MM`, `coronal=MM`, `sagittal=MM` (each optionally `:flip`) or `NX,NY,NZ,D`.
    pub fn parse(text: &str) -> Result<ClipPlane, String> {
        let (body, flip) = match text.trim().strip_suffix(":flip") {
            Some(b) => (b, true),
            None => (text.trim(), false),
        };
        let number = |s: &str| s.trim().parse::<f32>().ok().filter(|v| v.is_finite());
        let plane = if let Some((name, mm)) = body.split_once('=') {
            let normal = match name.trim().to_ascii_lowercase().as_str() {
                "axial" => Vec3::Z,
                "coronal" => Vec3::Y,
                "sagittal" => Vec3::X,
                other => return Err(format!("unknown plane \"{other}\" (axial, coronal, sagittal or NX,NY,NZ,D)")),
            };
            let mm = number(mm).ok_or_else(|| format!("\"{mm}\" is not a position in millimetres"))?;
            ClipPlane::new(normal, mm)
        } else {
            let v: Vec<f32> = body.split(',').filter_map(number).collect();
            if v.len() != 4 || body.split(',').count() != 4 {
                return Err(format!("\"{text}\": give axial=MM, coronal=MM, sagittal=MM or NX,NY,NZ,D"));
            }
            Some(ClipPlane::new(Vec3::new(v[0], v[1], v[2]), v[3]).ok_or("a plane's normal cannot be zero")?)
        };
        let plane = plane.ok_or_else(|| format!("\"{text}\" is not a plane"))?;
        Ok(if flip { plane.flipped() } else { plane })
    }

    /// The same plane keeping the other side.
    pub fn flipped(self) -> ClipPlane {
        ClipPlane { normal: self.normal.map(|c| -c), d: -self.d }
    }

    pub fn normal(&self) -> Vec3 {
        Vec3::from(self.normal)
    }

    /// Does it remove this point?
    pub fn removes(&self, p: Vec3) -> bool {
        self.normal().dot(p) > self.d
    }

    /// Does it pass through these bounds (some corner kept, some removed)?
    pub fn crosses(&self, b: &Bounds) -> bool {
        let c = b.corners();
        c.iter().any(|&p| self.removes(p)) && c.iter().any(|&p| !self.removes(p))
    }

    /// The plane as the shaders read it: normal and offset.
    pub fn to_vec4(&self) -> [f32; 4] {
        [self.normal[0], self.normal[1], self.normal[2], self.d]
    }
}

/// How far (millimetres along a unit normal) a box must lie from a plane to count as wholly on
/// one side: the shaders test interpolated points, a little off the triangles' own arithmetic, so
/// a box closer than this counts as cut.
pub const SIDE_MARGIN_MM: f32 = 0.01;

/// Where `b` lies against `planes` (within [`SIDE_MARGIN_MM`] of a plane counts as cut).
pub fn side(planes: &[ClipPlane], b: &Bounds) -> Side {
    side_within(planes, b, SIDE_MARGIN_MM)
}

/// Where `b` lies against `planes`, within `margin` millimetres of a plane counting as cut.
pub fn side_within(planes: &[ClipPlane], b: &Bounds, margin: f32) -> Side {
    let mut cut = false;
    for p in planes {
        let margin = margin * p.normal().length();
        let along = b.corners().map(|c| p.normal().dot(c));
        if along.iter().all(|&a| a > p.d + margin) {
            return Side::Removed;
        }
        cut |= along.iter().any(|&a| a > p.d - margin);
    }
    if cut {
        Side::Cut
    } else {
        Side::Kept
    }
}

/// A plane in a model's space: normal and offset, removing `n . q > d`.
pub type ModelPlane = (Vec3, f32);

/// The planes the shaders apply (the first [`MAX_PLANES`]) in the space of `model`'s input, as
/// (normal, offset): world n.p > d is (A^T n).q > d - n.t for p = A q + t, and the difference
/// (A^T n).q - (d - n.t) is the world distance n.p - d, so margins stay in millimetres.
pub fn in_model_space(planes: &[ClipPlane], model: &glam::Mat4) -> Vec<ModelPlane> {
    let (linear, shift) = (glam::Mat3::from_mat4(*model), model.w_axis.truncate());
    planes.iter().take(MAX_PLANES).map(|p| (linear.transpose() * p.normal(), p.d - p.normal().dot(shift))).collect()
}

/// A corner of a polygon to cut: where it lies, and the corner a share `t` of the way to another.
pub trait Corner: Copy {
    fn position(self) -> Vec3;
    fn lerp(self, other: Self, t: f32) -> Self;
}

impl Corner for Vec3 {
    fn position(self) -> Vec3 {
        self
    }
    fn lerp(self, other: Vec3, t: f32) -> Vec3 {
        Vec3::lerp(self, other, t)
    }
}

/// The part of the convex polygon `polygon` that the plane `(n, d)` keeps (`n · p <= d`;
/// Sutherland-Hodgman), in the same winding.
pub fn clip_polygon<C: Corner>(polygon: &[C], (n, d): ModelPlane) -> Vec<C> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        let (da, db) = (n.dot(a.position()) - d, n.dot(b.position()) - d);
        if da <= 0.0 {
            out.push(a);
        }
        if (da <= 0.0) != (db <= 0.0) {
            out.push(crossing(a, b, (n, d)));
        }
    }
    out
}

/// Where the edge from `a` to `b` crosses the plane `(n, d)`. Computed from the lesser end (by
/// position) so that both polygons of an edge get the very same point.
pub fn crossing<C: Corner>(a: C, b: C, (n, d): ModelPlane) -> C {
    let (a, b) = if a.position().to_array() <= b.position().to_array() { (a, b) } else { (b, a) };
    let (da, db) = (n.dot(a.position()) - d, n.dot(b.position()) - d);
    a.lerp(b, da / (da - db))
}

/// Where triangle `tri` lies against `planes` (in its space): kept where every plane keeps every
/// corner by `margin` millimetres, as [`clip_triangle`] decides.
pub fn triangle_side(tri: [Vec3; 3], planes: &[ModelPlane], margin: f32) -> Side {
    let mut side = Side::Kept;
    for &(n, d) in planes {
        let kept = tri.map(|p| n.dot(p) - (d - margin) <= 0.0);
        if kept == [false; 3] {
            return Side::Removed;
        }
        if kept != [true; 3] {
            side = Side::Cut;
        }
    }
    side
}

/// The part of triangle `tri` that every plane of `planes` (in its space) keeps by `margin`
/// millimetres (`n · p <= d - margin`): a convex polygon in the triangle's winding, empty where
/// nothing is kept.
pub fn clip_triangle(tri: [Vec3; 3], planes: &[ModelPlane], margin: f32) -> Vec<Vec3> {
    let mut polygon = tri.to_vec();
    for &(n, d) in planes {
        polygon = clip_polygon(&polygon, (n, d - margin));
        if polygon.len() < 3 {
            return Vec::new();
        }
    }
    polygon
}

/// The planes for the shaders: the first [`MAX_PLANES`], the rest removing nothing.
pub fn uniform(planes: &[ClipPlane]) -> [[f32; 4]; MAX_PLANES] {
    let mut out = [[0.0, 0.0, 0.0, f32::MAX]; MAX_PLANES];
    for (o, p) in out.iter_mut().zip(planes) {
        *o = p.to_vec4();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn named_planes_remove_the_side_they_name() {
        let axial = ClipPlane::parse("axial=10").unwrap();
        assert!(axial.removes(Vec3::new(0.0, 0.0, 11.0)) && !axial.removes(Vec3::new(0.0, 0.0, 9.0)));
        let coronal = ClipPlane::parse("coronal=-5:flip").unwrap();
        assert!(coronal.removes(Vec3::new(0.0, -6.0, 0.0)) && !coronal.removes(Vec3::ZERO));
        let sagittal = ClipPlane::parse("Sagittal=0").unwrap();
        assert!(sagittal.removes(Vec3::X));
        let general = ClipPlane::parse("0,0,2,4").unwrap();
        assert_eq!((general.normal, general.d), ([0.0, 0.0, 1.0], 2.0), "normalised");
        for bad in ["axial=x", "axial=NaN", "0,0,0,1", "1,2,3", "oblique=3", "1,2,3,inf"] {
            assert!(ClipPlane::parse(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn triangles_are_cut_to_what_the_planes_keep() {
        let tri = [Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0)];
        let x_below_1: ModelPlane = (Vec3::X, 1.0);
        // Kept wholly, removed wholly, and cut into a quadrilateral of the same winding.
        assert_eq!(clip_triangle(tri, &[(Vec3::X, 5.0)], 0.0), tri.to_vec());
        assert!(clip_triangle(tri, &[(-Vec3::X, -5.0)], 0.0).is_empty());
        assert_eq!(triangle_side(tri, &[(Vec3::X, 5.0)], 0.0), Side::Kept);
        assert_eq!(triangle_side(tri, &[(-Vec3::X, -5.0)], 0.0), Side::Removed);
        assert_eq!(triangle_side(tri, &[(Vec3::X, 5.0), x_below_1], 0.0), Side::Cut);
        assert_eq!(triangle_side(tri, &[(Vec3::X, 2.5)], 0.6), Side::Cut, "within the margin");
        let cut = clip_triangle(tri, &[x_below_1], 0.0);
        assert_eq!(cut, [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 2.0, 0.0)]);
        let area = |p: &[Vec3]| (1..p.len() - 1).map(|i| (p[i] - p[0]).cross(p[i + 1] - p[0]).z).sum::<f32>() / 2.0;
        assert!((area(&cut) - 1.5).abs() < 1e-6);
        // The margin keeps the polygon that far inside; two planes cut a corner off twice.
        let inset = clip_triangle(tri, &[x_below_1], 0.25);
        assert!(inset.iter().all(|p| p.x <= 0.75 + 1e-6) && inset.iter().any(|p| (p.x - 0.75).abs() < 1e-6));
        let both = clip_triangle(tri, &[x_below_1, (Vec3::Y, 1.0)], 0.0);
        assert!((area(&both) - 1.0).abs() < 1e-6, "the unit square: {both:?}");
    }

    #[test]
    fn boxes_are_kept_removed_or_cut() {
        let b = Bounds { min: [0.0; 3], max: [1.0; 3] };
        let at = |mm| [ClipPlane::parse(&format!("axial={mm}")).unwrap()];
        assert_eq!(side(&at(2.0), &b), Side::Kept);
        assert_eq!(side(&at(-1.0), &b), Side::Removed);
        assert_eq!(side(&at(0.5), &b), Side::Cut);
        assert_eq!(uniform(&at(0.5))[1], [0.0, 0.0, 0.0, f32::MAX]);
    }
}
