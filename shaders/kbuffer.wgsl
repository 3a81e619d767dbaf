// The k-buffer's resolve (Callahan 2005, ch. 3), screen pixels: a pixel's k slots, nearest first,
// composited front to back over the image below them (the opaque organs with the faded fragments
// farther than the k nearest blended in). Slots and keys as in organ.wgsl's fs_kbuffer_*: a key
// of 0 is an empty slot; a colour is the square root of linear RGB and the opacity, 8 bits each.
// Keep KBuffer in sync with KBufferUniform in src/render/uniforms.rs.

struct KBuffer {
    width: u32,
    height: u32,
    k: u32,
    pad: u32,
};

@group(0) @binding(0) var<uniform> kbuffer: KBuffer;
@group(0) @binding(1) var<storage, read> keys: array<u32>;
@group(0) @binding(2) var<storage, read> colours: array<u32>;
@group(0) @binding(3) var below: texture_2d<f32>;

@vertex
fn vs_fullscreen(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs_resolve(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    let at = vec2<u32>(p.xy);
    let first = (at.y * kbuffer.width + at.x) * kbuffer.k;
    var colour = vec3<f32>(0.0);
    var through = 1.0;
    for (var i = 0u; i < kbuffer.k; i++) {
        if keys[first + i] == 0u {
            break;
        }
        let c = unpack4x8unorm(colours[first + i]);
        colour += through * c.a * c.rgb * c.rgb;
        through *= 1.0 - c.a;
    }
    let b = textureLoad(below, vec2<i32>(at), 0);
    return vec4<f32>(colour + through * b.rgb, 1.0 - through * (1.0 - b.a));
}
