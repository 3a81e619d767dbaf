// Full-screen passes of the depth-peeling modes (src/render/peel.rs), per MSAA sample, screen
// pixels. Entry points: vs_fullscreen (all), fs_sample (a sample of `layer` as it is: a peeled
// layer blended under the layers before it, or the opaque image under all of them), fs_back (a dual
// peeling pass's back layer, blended over the back layers before it; samples without one are
// discarded, so an occlusion query counts what the pass peeled from the back) and fs_dual_final
// (the front layers over the back layers and the opaque image).

@group(0) @binding(0) var layer: texture_multisampled_2d<f32>;
@group(0) @binding(1) var back: texture_multisampled_2d<f32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_sample(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> @location(0) vec4<f32> {
    return textureLoad(layer, vec2<i32>(p.xy), i32(s));
}

@fragment
fn fs_back(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> @location(0) vec4<f32> {
    let c = textureLoad(layer, vec2<i32>(p.xy), i32(s));
    if c.a <= 0.0 {
        discard;
    }
    return c;
}

@fragment
fn fs_dual_final(@builtin(position) p: vec4<f32>, @builtin(sample_index) s: u32) -> @location(0) vec4<f32> {
    let at = vec2<i32>(p.xy);
    let f = textureLoad(layer, at, i32(s));
    let b = textureLoad(back, at, i32(s));
    return vec4<f32>(f.rgb + (1.0 - f.a) * b.rgb, 1.0 - (1.0 - f.a) * (1.0 - b.a));
}
