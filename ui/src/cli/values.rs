//! The command line's value types and their clap parsers: the core's enums offered by name,
//! sizes `WxH`, orbits `AZ,EL`, opacities `ID=A` and bench routes `ROUTE:FRAME`.
//!
//! - Enums are thin [`clap::ValueEnum`] wrappers, so every value and its help come from the
//!   core's `ALL` and `name()`.
//! - A bad value is refused while the arguments are parsed, before any file is read, with clap's
//!   message naming the option (and listing the choices, for enums).

use anyhow::{anyhow, bail, Result};
use clap::builder::{EnumValueParser, PossibleValue, TypedValueParser};
use std::ffi::OsStr;
use vbrain::camera::View;
use vbrain::cull::{CullMode, Selection};
use vbrain::lab::bench::Route;
use vbrain::transparency::TransparencyMode;

/// A [`clap::ValueEnum`] over a core enum: its values are the core's `ALL`, named by its `name()`,
/// with extra spellings from `aliases`.
macro_rules! value_enum {
    ($(#[$doc:meta])* $wrapper:ident($core:ty) $(, aliases: [$(($variant:expr, $alias:literal)),* $(,)?])?) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct $wrapper(pub $core);

        impl clap::ValueEnum for $wrapper {
            fn value_variants<'a>() -> &'a [Self] {
                static ALL: std::sync::OnceLock<Vec<$wrapper>> = std::sync::OnceLock::new();
                ALL.get_or_init(|| <$core>::ALL.iter().map(|&v| $wrapper(v)).collect())
            }

            fn to_possible_value(&self) -> Option<PossibleValue> {
                let aliases: &[($core, &str)] = &[$($(($variant, $alias)),*)?];
                let aliases = aliases.iter().filter(|(v, _)| *v == self.0).map(|(_, a)| *a);
                Some(PossibleValue::new(self.0.name()).aliases(aliases))
            }
        }
    };
}

value_enum!(
    /// A standard view (anterior, posterior, ...); matched ignoring case where the option says so.
    ViewArg(View)
);
value_enum!(
    /// A culling mode: none, frustum or occlusion.
    CullArg(CullMode)
);
value_enum!(
    /// How faded organs are drawn.
    TransparencyArg(TransparencyMode)
);
value_enum!(
    /// How occluders are chosen; `ps` is short for projected size.
    SelectionArg(Selection),
    aliases: [(Selection::ProjectedSize, "ps")]
);
value_enum!(
    /// What colours the organs.
    ColourByArg(vbrain::layout::ColourBy)
);
value_enum!(
    /// A camera path: the orbit or a city walkthrough route.
    RouteArg(Route)
);
value_enum!(
    /// What solid cut faces show.
    CutFaceArg(vbrain::clip::CutFaceShows),
    aliases: [(vbrain::clip::CutFaceShows::Colour, "color")]
);

/// The parser of a core enum by name, giving the core's value.
fn core<W: clap::ValueEnum + Clone + Send + Sync + 'static, T: Clone + Send + Sync + 'static>(
    unwrap: fn(W) -> T,
) -> impl TypedValueParser<Value = T> {
    EnumValueParser::<W>::new().map(unwrap)
}

pub fn view() -> impl TypedValueParser<Value = View> {
    core(|v: ViewArg| v.0)
}

pub fn cull_mode() -> impl TypedValueParser<Value = CullMode> {
    core(|v: CullArg| v.0)
}

/// A culling mode in a comma-separated list: spaces around it are ignored.
pub fn cull_mode_in_list() -> impl TypedValueParser<Value = CullMode> {
    Trimmed(cull_mode())
}

pub fn transparency_mode() -> impl TypedValueParser<Value = TransparencyMode> {
    core(|v: TransparencyArg| v.0)
}

pub fn cut_face() -> impl TypedValueParser<Value = vbrain::clip::CutFaceShows> {
    core(|v: CutFaceArg| v.0)
}

pub fn colour_by() -> impl TypedValueParser<Value = vbrain::layout::ColourBy> {
    core(|v: ColourByArg| v.0)
}

pub fn selection() -> impl TypedValueParser<Value = Selection> {
    core(|v: SelectionArg| v.0)
}

pub fn route() -> impl TypedValueParser<Value = Route> {
    core(|v: RouteArg| v.0)
}

/// A parser that trims spaces off the value before `P` reads it.
#[derive(Clone)]
struct Trimmed<P>(P);

impl<P: TypedValueParser> TypedValueParser for Trimmed<P> {
    type Value = P::Value;

    fn parse_ref(&self, cmd: &clap::Command, arg: Option<&clap::Arg>, value: &OsStr) -> Result<P::Value, clap::Error> {
        match value.to_str() {
            Some(s) => self.0.parse_ref(cmd, arg, OsStr::new(s.trim())),
            None => self.0.parse_ref(cmd, arg, value),
        }
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        self.0.possible_values()
    }
}

/// An image or raster size in pixels, `WxH` (or `WXH`), each side in 1..=16384.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Size {
    pub width: u32,
    pub height: u32,
}

pub fn size(s: &str) -> Result<Size> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| anyhow!("size \"{s}\" is not WxH"))?;
    let side = |v: &str, what: &str| v.trim().parse::<u32>().map_err(|e| anyhow!("{what} in \"{s}\": {e}"));
    let (width, height) = (side(w, "width")?, side(h, "height")?);
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        bail!("size {width}x{height} outside 1..16384");
    }
    Ok(Size { width, height })
}

/// A culling raster size, `WxH`, each side in 16..=2048 (the occlusion maps cost W*H per frame).
pub fn raster_size(s: &str) -> Result<Size> {
    let size = size(s)?;
    if !(16..=2048).contains(&size.width) || !(16..=2048).contains(&size.height) {
        bail!("raster {}x{} outside 16..2048 per side", size.width, size.height);
    }
    Ok(size)
}

/// A number in `lo..=hi` (finite).
pub fn float_in(lo: f64, hi: f64) -> impl TypedValueParser<Value = f64> {
    move |s: &str| -> Result<f64> {
        let v: f64 = s.trim().parse().map_err(|e| anyhow!("\"{s}\": {e}"))?;
        if !(lo..=hi).contains(&v) {
            bail!("{v} outside {lo}..={hi}");
        }
        Ok(v)
    }
}

/// A number in `lo..=hi` (finite), as an `f32`.
pub fn f32_in(lo: f64, hi: f64) -> impl TypedValueParser<Value = f32> {
    float_in(lo, hi).map(|v| v as f32)
}

/// A share or opacity in 0..=1.
pub fn unit(s: &str) -> Result<f32> {
    let v: f32 = s.trim().parse().map_err(|e| anyhow!("\"{s}\": {e}"))?;
    if !(0.0..=1.0).contains(&v) {
        bail!("{v} outside 0..1");
    }
    Ok(v)
}

/// Camera angles around the set, `AZ,EL` in degrees from the anterior view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orbit {
    pub azimuth: f32,
    pub elevation: f32,
}

pub fn orbit(s: &str) -> Result<Orbit> {
    let (az, el) = s.split_once(',').ok_or_else(|| anyhow!("orbit \"{s}\" is not AZ,EL"))?;
    let angle = |v: &str, what: &str| {
        let a = v.trim().parse::<f32>().map_err(|e| anyhow!("{what} in \"{s}\": {e}"))?;
        // Beyond a turn's many multiples, degrees lose the precision of a pixel.
        if !(a.is_finite() && a.abs() <= 1e6) {
            bail!("{what} {a} in \"{s}\" is not a number of degrees within +-1000000");
        }
        Ok(a)
    };
    Ok(Orbit { azimuth: angle(az, "azimuth")?, elevation: angle(el, "elevation")? })
}

/// An organ's opacity, `ID=A` (`all=A` for every organ), A in 0..=1.
#[derive(Clone, Debug, PartialEq)]
pub struct OrganOpacity {
    pub id: String,
    pub opacity: f32,
}

pub fn organ_opacity(s: &str) -> Result<OrganOpacity> {
    let (id, a) = s.split_once('=').ok_or_else(|| anyhow!("opacity \"{s}\" is not ID=A"))?;
    let opacity: f32 = a.parse().map_err(|e| anyhow!("opacity in \"{s}\": {e}"))?;
    if !(0.0..=1.0).contains(&opacity) {
        bail!("opacity {opacity} in \"{s}\" outside 0..1");
    }
    Ok(OrganOpacity { id: id.to_string(), opacity })
}

/// Frames of a bench route that `--route` of `vbrain render` picks from.
pub const ROUTE_FRAMES: usize = 120;

/// A frame of a bench route, `ROUTE:FRAME` (`ROUTE` alone is frame 0), FRAME in 0..120.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RouteFrame {
    pub route: Route,
    pub frame: usize,
}

pub fn route_frame(s: &str) -> Result<RouteFrame> {
    let (route, frame) = s.split_once(':').unwrap_or((s, "0"));
    let frame: usize = frame.trim().parse().map_err(|e| anyhow!("frame in \"{s}\": {e}"))?;
    if frame >= ROUTE_FRAMES {
        bail!("frame {frame} outside 0..{ROUTE_FRAMES}");
    }
    let route =
        Route::parse(route).ok_or_else(|| anyhow!("unknown route \"{route}\" (orbit, best, average, worst)"))?;
    Ok(RouteFrame { route, frame })
}

/// Screen-door sub-samples per pixel: one of the core's choices.
pub fn subsamples(s: &str) -> Result<usize> {
    let n: usize = s.trim().parse().map_err(|e| anyhow!("\"{s}\": {e}"))?;
    let choices = vbrain::transparency::SUBSAMPLE_CHOICES;
    if !choices.contains(&n) {
        let names: Vec<String> = choices.iter().map(|c| c.to_string()).collect();
        bail!("use {}", names.join(", "));
    }
    Ok(n)
}

/// A clip plane: `axial=MM`, `coronal=MM`, `sagittal=MM` (`:flip` keeps the other side) or
/// `NX,NY,NZ,D`.
pub fn clip_plane(s: &str) -> Result<vbrain::clip::ClipPlane> {
    vbrain::clip::ClipPlane::parse(s).map_err(|e| anyhow!(e))
}

/// `on` or `off`.
pub fn on_off(s: &str) -> Result<bool> {
    match s.to_ascii_lowercase().as_str() {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => bail!("\"{s}\": give on or off"),
    }
}

/// A quiz mode: locate, name or mixed.
pub fn quiz_mode(s: &str) -> Result<vbrain::quiz::Mode> {
    vbrain::quiz::Mode::parse(s).ok_or_else(|| anyhow::anyhow!("\"{s}\": give locate, name, mixed, mri or supply"))
}

/// A slice plane, `axial=MM`, `coronal=MM` or `sagittal=MM`.
pub fn slice_plane(s: &str) -> Result<vbrain::mri::slice::SlicePlane> {
    vbrain::mri::slice::SlicePlane::parse(s).map_err(|e| anyhow!(e))
}

/// An MRI window and level, `WINDOW,LEVEL` (normalised intensities).
pub fn window(s: &str) -> Result<vbrain::mri::Window> {
    let (w, l) = s.split_once(',').ok_or_else(|| anyhow!("\"{s}\" is not WINDOW,LEVEL, e.g. 0.8,0.45"))?;
    let number = |v: &str| v.trim().parse::<f32>().map_err(|_| anyhow!("\"{v}\" in \"{s}\" is not a number"));
    vbrain::mri::Window::new(number(w)?, number(l)?).map_err(|e| anyhow!(e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::ValueEnum;

    #[test]
    fn orbits_are_finite_angles() {
        assert_eq!(orbit("30, -15").unwrap(), Orbit { azimuth: 30.0, elevation: -15.0 });
        for bad in ["1e309,0", "nan,nan", "0,inf", "1e7,0", "30", "a,b"] {
            assert!(orbit(bad).is_err(), "{bad} accepted");
        }
    }

    #[test]
    fn enums_offer_every_core_value_by_its_name() {
        let names = |v: Vec<PossibleValue>| v.iter().map(|p| p.get_name().to_string()).collect::<Vec<_>>();
        let of = |w: &[CullArg]| names(w.iter().filter_map(|w| w.to_possible_value()).collect());
        assert_eq!(of(CullArg::value_variants()), ["none", "frustum", "occlusion"]);
        assert_eq!(TransparencyArg::value_variants().len(), TransparencyMode::ALL.len());
        assert_eq!(RouteArg::value_variants().len(), Route::ALL.len());
        assert_eq!(ViewArg::from_str("Left", true), Ok(ViewArg(View::Left)));
        assert!(ViewArg::from_str("sideways", true).is_err());
        for s in ["ps", "projected-size"] {
            assert_eq!(SelectionArg::from_str(s, false), Ok(SelectionArg(Selection::ProjectedSize)));
        }
        assert_eq!(SelectionArg::from_str("mos", false), Ok(SelectionArg(Selection::Mos)));
    }

    #[test]
    fn values_accept_and_refuse_as_before() {
        assert_eq!(size(" 96 X64").ok(), Some(Size { width: 96, height: 64 }));
        for bad in ["0x10", "big", "10x", "16385x1", "-1x2"] {
            assert!(size(bad).is_err(), "{bad}");
        }
        assert_eq!(orbit("-30, 20").ok(), Some(Orbit { azimuth: -30.0, elevation: 20.0 }));
        assert!(orbit("1").is_err() && orbit("a,b").is_err());
        assert_eq!(organ_opacity("all=0.8").ok(), Some(OrganOpacity { id: "all".into(), opacity: 0.8 }));
        for bad in ["frontal_l=2", "frontal_l", "x= 0.5", "x=NaN"] {
            assert!(organ_opacity(bad).is_err(), "{bad}");
        }
        assert_eq!(route_frame("best").ok(), Some(RouteFrame { route: Route::Best, frame: 0 }));
        assert_eq!(route_frame("worst: 119").ok(), Some(RouteFrame { route: Route::Worst, frame: 119 }));
        for bad in ["best:120", "sideways:1", "best:x"] {
            assert!(route_frame(bad).is_err(), "{bad}");
        }
        assert_eq!(subsamples("16").ok(), Some(16));
        assert!(subsamples("12").is_err());
    }
}
