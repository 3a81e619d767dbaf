// Full-screen passes over float images (texel loads, no filtering), screen pixels.
// Entry points: vs_fullscreen (all), fs_copy (the "accumulate" pipeline, which blends each
// screen-door pass in with a constant weight, and the "present" pipeline, which writes the result
// to the sRGB target), fs_weighted_resolve (weighted blended OIT over the opaque image),
// fs_outline (rings where the outline mask changes to another organ's number: red channel
// highlighted organs, green the selected one; OUTLINE_WIDTH is outline::WIDTH in src/render/).

@group(0) @binding(0) var image: texture_2d<f32>;
@group(0) @binding(1) var accum: texture_2d<f32>;
@group(0) @binding(2) var reveal: texture_2d<f32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_copy(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    return textureLoad(image, vec2<i32>(p.xy), 0);
}

@fragment
fn fs_weighted_resolve(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let at = vec2<i32>(p.xy);
    let opaque = textureLoad(image, at, 0);
    let a = textureLoad(accum, at, 0);
    let r = textureLoad(reveal, at, 0).r;
    let colour = a.rgb / max(a.a, 1e-5);
    return vec4<f32>(opaque.rgb * r + colour * (1.0 - r), 1.0 - (1.0 - opaque.a) * r);
}

const OUTLINE_WIDTH: i32 = 2;
// Linear light: amber (sRGB 255, 190, 0) for highlights, sky blue (sRGB 80, 220, 255) for selection.
const HIGHLIGHT: vec3<f32> = vec3<f32>(1.0, 0.515, 0.0);
const SELECTED: vec3<f32> = vec3<f32>(0.08, 0.716, 1.0);

@fragment
fn fs_outline(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let at = vec2<i32>(p.xy);
    let size = vec2<i32>(textureDimensions(image));
    let here = textureLoad(image, at, 0).rg;
    // Does a pixel within the ring's reach hold another (nonzero) organ number, per channel?
    var other = vec2<bool>(false);
    for (var dy = -OUTLINE_WIDTH; dy <= OUTLINE_WIDTH; dy++) {
        for (var dx = -OUTLINE_WIDTH; dx <= OUTLINE_WIDTH; dx++) {
            let q = at + vec2<i32>(dx, dy);
            if (dx * dx + dy * dy <= OUTLINE_WIDTH * OUTLINE_WIDTH + 1 && all(q >= vec2<i32>(0)) && all(q < size)) {
                let there = textureLoad(image, q, 0).rg;
                other = other | ((there > vec2<f32>(0.5)) & (abs(there - here) > vec2<f32>(0.5)));
            }
        }
    }
    // Around a silhouette, and along the line between two highlighted organs.
    if (other.g) {
        return vec4<f32>(SELECTED, 1.0);
    }
    if (other.r) {
        return vec4<f32>(HIGHLIGHT, 1.0);
    }
    return vec4<f32>(0.0);
}
