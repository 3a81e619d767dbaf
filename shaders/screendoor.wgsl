// Screen-door's tiles (src/render/screendoor.rs), in pixels. Each pass of the faded organs draws
// into its own tile of an atlas, a copy of the rectangle of the screen that faded organs cover:
// atlas pixel = screen pixel + offset. Entry points: vs_fullscreen (both), fs_restore (the "tile
// restore" pipeline: per MSAA sample, the opaque image's colour and depth into a tile, so that the
// faded organs are drawn over and tested against the opaque organs drawn once) and fs_gather (the
// "gather" pipeline: a round of tiles, resolved, averaged into the screen rectangle).
// Keep Screendoor in sync with organ.wgsl and ScreendoorUniform, Gather with GatherUniform.

struct Screendoor {
    region_px: u32,
    cols: u32,
    rows: u32,
    organs: u32,
    offset: vec2<i32>,
    pass_index: u32,
    pad: u32,
};

@group(0) @binding(0) var<uniform> screendoor: Screendoor;
@group(0) @binding(1) var opaque_colour: texture_multisampled_2d<f32>;
@group(0) @binding(2) var opaque_depth: texture_depth_multisampled_2d;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

struct Restored {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_restore(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> Restored {
    let at = vec2<i32>(p.xy) - screendoor.offset;
    var out: Restored;
    out.colour = textureLoad(opaque_colour, at, i32(s));
    out.depth = textureLoad(opaque_depth, at, i32(s));
    return out;
}

struct Gather {
    // Top-left screen pixel of the rectangle, and the distance between tiles (its size and a gap).
    origin: vec2<i32>,
    tile: vec2<i32>,
    // Tiles per atlas row, and the tiles of this round: `count` from tile `first`.
    tiles_x: u32,
    first: u32,
    count: u32,
    pad: u32,
};

// Bindings apart from fs_restore's: each entry point has its own bind group layout.
@group(0) @binding(3) var<uniform> gather: Gather;
@group(0) @binding(4) var tiles: texture_2d<f32>;

@fragment
fn fs_gather(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let local = vec2<i32>(p.xy) - gather.origin;
    var sum = vec4<f32>(0.0);
    for (var t = gather.first; t < gather.first + gather.count; t++) {
        let corner = vec2<i32>(i32(t % gather.tiles_x), i32(t / gather.tiles_x)) * gather.tile;
        sum += textureLoad(tiles, corner + local, 0);
    }
    return sum / f32(max(gather.count, 1u));
}
