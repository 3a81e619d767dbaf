// Full-screen passes over float images (texel loads, no filtering), screen pixels.
// Entry points: vs_fullscreen (all), fs_copy (the "accumulate" pipeline, which blends each
// screen-door pass in with a constant weight, and the "present" pipeline, which writes the result
// to the sRGB target), fs_weighted_resolve (weighted blended OIT over the opaque image).

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
