// Organ shading: world-space vertices (model matrix applied here), headlight lighting. Each vertex
// carries its organ's index, which selects the organ's data; organs drawn by one call may differ.
// Entry points: vs_main (all organ pipelines), fs_shade (opaque, blended and layer pipelines),
// fs_peel (a layer of depth peeling), fs_dual_init and fs_dual_peel (dual depth peeling),
// fs_pick (the "organ pick" pipeline writing organ IDs), fs_pick_instance (the "leaf pick"
// pipeline writing the instance index, which the benchmark sets to a leaf number), fs_screendoor
// (transparent organs through their sub-sample masks), fs_weighted (weighted blended OIT) and
// fs_mask (the outline mask: the organ's colour slot holds its mask channels), fs_kbuffer_depth and
// fs_kbuffer_shade (the k-buffer's two passes; their resolve is in kbuffer.wgsl).
// Keep in sync with FrameUniform, OrganUniform and ScreendoorUniform in src/render/. The
// peeling entry points take the sample index, so they run per MSAA sample.

struct Frame {
    view_proj: mat4x4<f32>,
    // Camera position in world space (w unused).
    eye: vec4<f32>,
    // Where this pass draws: NDC x' = x * zw + xy (a sub-pixel shift, or a screen-door tile of the
    // atlas; zw is (1, 1) otherwise).
    jitter: vec4<f32>,
    // Clip planes: xyz the unit normal, w the offset; a point p is removed where dot(n, p) > w.
    clip: array<vec4<f32>, 4>,
    // Organ space (millimetres) -> the MRI texture's coordinates.
    mri: mat4x4<f32>,
    // What cut faces show: x 0 colour, 1 MRI, 2 MRI tinted by the organ; y window; z level.
    cut_face: vec4<f32>,
    // x: 1 where a vertex's territory colour replaces its organ's.
    colour_by: vec4<u32>,
};

struct Organ {
    // Organ space -> world space.
    model: mat4x4<f32>,
    // Inverse transpose of model's upper 3x3, as columns of a 4x4 (fourth unused).
    normal_matrix: mat4x4<f32>,
    // Linear RGB and opacity.
    colour: vec4<f32>,
    // x: organ index + 1 (0 = background in the ID buffer); y: flags, CLIPPED | CAPPED | CLOSED.
    id: vec4<u32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
// The set's MRI (normalised intensity in r; 1 voxel where the set has none), sampled trilinearly.
@group(0) @binding(1) var mri_volume: texture_3d<f32>;
@group(0) @binding(2) var mri_sampler: sampler;
@group(1) @binding(0) var<storage, read> organs: array<Organ>;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) organ: u32,
    // sRGB bytes r, g, b, a from the low byte up; 0 where no territory covers the vertex.
    @location(3) territory: u32,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
    @location(3) @interpolate(flat) organ: u32,
    @location(4) @interpolate(flat) territory: u32,
};

@vertex
fn vs_main(in: VsIn, @builtin(instance_index) instance: u32) -> VsOut {
    return organ_vertex(in, instance);
}

// A vertex moved into world space and projected (vs_main; vs_clipped in organ_clip.wgsl).
fn organ_vertex(in: VsIn, instance: u32) -> VsOut {
    var out: VsOut;
    out.instance = instance;
    out.organ = in.organ;
    out.territory = in.territory;
    let organ = organs[in.organ];
    let world = organ.model * vec4<f32>(in.position, 1.0);
    let clip = frame.view_proj * world;
    out.clip = vec4<f32>(clip.xy * frame.jitter.zw + frame.jitter.xy * clip.w, clip.zw);
    out.world = world.xyz;
    out.normal = (organ.normal_matrix * vec4<f32>(in.normal, 0.0)).xyz;
    return out;
}

const CLIPPED: u32 = 1u;
const CAPPED: u32 = 2u;
const CLOSED: u32 = 4u;

// Whether the clip planes remove the fragment (organs they cut only).
fn removed(in: VsOut) -> bool {
    if (organs[in.organ].id.y & CLIPPED) != 0u {
        for (var k = 0; k < 4; k++) {
            if dot(frame.clip[k].xyz, in.world) > frame.clip[k].w {
                return true;
            }
        }
    }
    return false;
}

// Discards what the clip planes remove. Where the device has clip distances the vertex stage
// (vs_clipped) has cut the triangles at the planes already.
fn clip(in: VsOut) {
    if removed(in) {
        discard;
    }
}

// The colour of a fragment: lit, or for a capped organ's face turned away (its inside, seen
// through the cut) the flat colour of a cut face, or the MRI where the cut face is.
fn surface(in: VsOut, front: bool) -> vec3<f32> {
    let organ = organs[in.organ];
    if !front && (organ.id.y & CAPPED) != 0u {
        let flat = organ.colour.rgb * 0.82;
        if frame.cut_face.x < 0.5 {
            return flat;
        }
        let v = mri_on_cut(in);
        if v < 0.0 {
            return flat;
        }
        let grey = srgb_to_linear(clamp((v - frame.cut_face.z) / max(frame.cut_face.y, 0.001) + 0.5, 0.0, 1.0));
        if frame.cut_face.x < 1.5 {
            return vec3<f32>(grey);
        }
        return grey * (0.25 + 0.75 * organ.colour.rgb / max(max(organ.colour.r, organ.colour.g), max(organ.colour.b, 0.05)));
    }
    return shade(in);
}

// The MRI's intensity where the eye sees the cut face through this back face: the ray from the eye
// enters the kept side at the farthest plane it crosses from the removed side. The point goes back
// into organ space (the MRI moves with its organ), then into the volume; -1 outside it.
fn mri_on_cut(in: VsOut) -> f32 {
    let eye = frame.eye.xyz;
    let ray = in.world - eye;
    var t = 0.0;
    for (var k = 0; k < 4; k++) {
        let n = frame.clip[k].xyz;
        let along = dot(n, ray);
        if any(n != vec3<f32>(0.0)) && dot(n, eye) > frame.clip[k].w && along < 0.0 {
            t = max(t, (frame.clip[k].w - dot(n, eye)) / along);
        }
    }
    let world = eye + ray * t;
    let organ = organs[in.organ];
    let inverse = transpose(mat3x3<f32>(organ.normal_matrix[0].xyz, organ.normal_matrix[1].xyz, organ.normal_matrix[2].xyz));
    let local = inverse * (world - organ.model[3].xyz);
    let uvw = (frame.mri * vec4<f32>(local, 1.0)).xyz;
    if any(uvw < vec3<f32>(0.0)) || any(uvw > vec3<f32>(1.0)) {
        return -1.0;
    }
    return textureSampleLevel(mri_volume, mri_sampler, uvw, 0.0).r;
}

// An sRGB component (0..1) in linear light.
fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        return c / 12.92;
    }
    return pow((c + 0.055) / 1.055, 2.4);
}

// The organ's colour (linear), or in territory colouring the vertex's territory's where it has one.
fn base_colour(in: VsOut) -> vec3<f32> {
    if frame.colour_by.x == 1u && in.territory != 0u {
        let c = unpack4x8unorm(in.territory).rgb;
        return vec3<f32>(srgb_to_linear(c.r), srgb_to_linear(c.g), srgb_to_linear(c.b));
    }
    return organs[in.organ].colour.rgb;
}

// Headlight: the light sits at the eye. Two-sided, so cut-open or inner faces are lit too.
fn shade(in: VsOut) -> vec3<f32> {
    let n = normalize(in.normal);
    let v = normalize(frame.eye.xyz - in.world);
    let ndl = abs(dot(n, v));
    let diffuse = base_colour(in) * (0.18 + 0.82 * ndl);
    let specular = vec3<f32>(0.18) * pow(ndl, 40.0);
    return diffuse + specular;
}

@fragment
fn fs_shade(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    clip(in);
    return vec4<f32>(surface(in, front), organs[in.organ].colour.a);
}

// Screen-door masks of this frame: per screen region a configuration, per configuration and organ
// a 64-bit mask (bit b = MSAA sample b % 4 of pass b / 4).
struct Screendoor {
    region_px: u32,
    cols: u32,
    rows: u32,
    organs: u32,
    // Where the pass's tile of the atlas lies: atlas pixel = screen pixel + offset.
    offset: vec2<i32>,
    // The pass being drawn: its four samples are bits 4 * pass .. 4 * pass + 3.
    pass_index: u32,
    pad: u32,
};

@group(2) @binding(0) var<uniform> screendoor: Screendoor;
@group(2) @binding(1) var<storage, read> region_config: array<u32>;
@group(2) @binding(2) var<storage, read> masks: array<vec2<u32>>;

// A well-mixed hash of a pixel's position (pixel_hash in src/transparency/region_keys.rs).
fn pixel_hash(p: vec2<u32>) -> u32 {
    var h = (p.x * 0x8da6b343u) ^ (p.y * 0xd8163841u);
    h ^= h >> 16u;
    h *= 0x7feb352du;
    h ^= h >> 15u;
    h *= 0x846ca68bu;
    return h ^ (h >> 16u);
}

// The region whose masks pixel px takes: the one under it moved by a hash of its position, at most
// half a region each way, so that neighbouring configurations blend instead of meeting at straight
// edges (region_of in src/transparency/region_keys.rs).
fn region_of(px: vec2<u32>) -> vec2<u32> {
    let reach = i32(screendoor.region_px / 2u);
    let h = pixel_hash(px);
    let span = u32(2 * reach + 1);
    let moved = max(vec2<i32>(px) + vec2<i32>(vec2<u32>(h & 0xffffu, h >> 16u) % span) - reach, vec2<i32>(0));
    let cell = vec2<u32>(moved) / max(screendoor.region_px, 1u);
    return min(cell, vec2<u32>(screendoor.cols, screendoor.rows) - 1u);
}

struct Masked {
    @location(0) colour: vec4<f32>,
    @builtin(sample_mask) mask: u32,
};

@fragment
fn fs_screendoor(in: VsOut, @builtin(front_facing) front: bool) -> Masked {
    clip(in);
    let px = vec2<u32>(max(vec2<i32>(in.clip.xy) - screendoor.offset, vec2<i32>(0)));
    let region = region_of(px);
    let config = region_config[region.y * screendoor.cols + region.x];
    let m = masks[config * screendoor.organs + in.organ];
    let word = select(m.x, m.y, screendoor.pass_index >= 8u);
    let bits = (word >> ((screendoor.pass_index % 8u) * 4u)) & 15u;
    if bits == 0u {
        discard;
    }
    var out: Masked;
    out.colour = vec4<f32>(surface(in, front), 1.0);
    out.mask = bits;
    return out;
}

// Weighted blended order-independent transparency (McGuire and Bavoil 2013, weight of eq. 10):
// accumulates premultiplied colour times weight, and the product of (1 - alpha) as revealage.
struct Weighted {
    @location(0) accum: vec4<f32>,
    @location(1) reveal: vec4<f32>,
};

@fragment
fn fs_weighted(in: VsOut, @builtin(front_facing) front: bool) -> Weighted {
    clip(in);
    let a = organs[in.organ].colour.a;
    let d = 1.0 - in.clip.z;
    let w = a * max(0.01, 3000.0 * d * d * d);
    var out: Weighted;
    out.accum = vec4<f32>(surface(in, front) * a, a) * w;
    out.reveal = vec4<f32>(a);
    return out;
}

// Depth peeling (Everitt 2001), per sample: the nearest faded surface behind the layer peeled
// last and in front of the opaque organs, premultiplied. Its depth is written as computed here, so
// the next layer's test against it is exact.
@group(2) @binding(0) var peeled_depth: texture_depth_multisampled_2d;
@group(2) @binding(1) var opaque_depth: texture_depth_multisampled_2d;

struct Peeled {
    @location(0) colour: vec4<f32>,
    @builtin(frag_depth) depth: f32,
};

@fragment
fn fs_peel(in: VsOut, @builtin(front_facing) front: bool, @builtin(sample_index) s: u32) -> Peeled {
    clip(in);
    let at = vec2<i32>(in.clip.xy);
    let z = in.clip.z;
    if z <= textureLoad(peeled_depth, at, i32(s)) || z >= textureLoad(opaque_depth, at, i32(s)) {
        discard;
    }
    let a = organs[in.organ].colour.a;
    var out: Peeled;
    out.colour = vec4<f32>(surface(in, front) * a, a);
    out.depth = z;
    return out;
}

// Dual depth peeling (Bavoil and Myers 2008), per sample, every target MAX-blended: the nearest
// and farthest depth still to peel (stored as -near and far), the front layers composited front to
// back (premultiplied), and this pass's back layer (straight alpha), which the renderer then
// blends over the back layers so far. The opaque organs' depth is the depth test.
@group(2) @binding(2) var dual_near: texture_multisampled_2d<f32>;
@group(2) @binding(3) var dual_far: texture_multisampled_2d<f32>;
@group(2) @binding(4) var dual_front: texture_multisampled_2d<f32>;

struct DualDepth {
    @location(0) near: vec4<f32>,
    @location(1) far: vec4<f32>,
};

@fragment
fn fs_dual_init(in: VsOut, @builtin(sample_index) s: u32) -> DualDepth {
    clip(in);
    // Per sample, as the peeling passes: their depths must match these bit for bit.
    let z = in.clip.z + f32(s) * 0.0;
    var out: DualDepth;
    out.near = vec4<f32>(-z);
    out.far = vec4<f32>(z);
    return out;
}

struct Dual {
    @location(0) near: vec4<f32>,
    @location(1) far: vec4<f32>,
    @location(2) front: vec4<f32>,
    @location(3) back: vec4<f32>,
};

@fragment
fn fs_dual_peel(in: VsOut, @builtin(front_facing) front: bool, @builtin(sample_index) s: u32) -> Dual {
    clip(in);
    let at = vec2<i32>(in.clip.xy);
    let z = in.clip.z;
    let near = -textureLoad(dual_near, at, i32(s)).r;
    let far = textureLoad(dual_far, at, i32(s)).r;
    let f = textureLoad(dual_front, at, i32(s));
    var out: Dual;
    // Passed through by default (MAX keeps the largest).
    out.near = vec4<f32>(-1.0);
    out.far = vec4<f32>(-1.0);
    out.front = f;
    out.back = vec4<f32>(0.0);
    if z < near || z > far {
        return out;
    }
    if z > near && z < far {
        out.near = vec4<f32>(-z);
        out.far = vec4<f32>(z);
        return out;
    }
    let c = vec4<f32>(surface(in, front), organs[in.organ].colour.a);
    if z == near {
        let through = 1.0 - f.a;
        out.front = vec4<f32>(f.rgb + c.rgb * c.a * through, 1.0 - through * (1.0 - c.a));
    } else {
        out.back = c;
    }
    return out;
}

// The k-buffer (Callahan 2005, ch. 3), per pixel: the k nearest faded fragments in front of the
// opaque organs, kept sorted by two passes over the faded triangles (drawn back to front by
// centroid, one pipeline with no face culling). fs_kbuffer_depth inserts each fragment's depth key
// into the pixel's k slots with atomicMax (a key is the depth's bits inverted, so the largest key
// is the nearest fragment and a cleared slot, 0, is empty): the slots end up holding the k nearest
// keys in order whatever the order fragments arrive in. fs_kbuffer_shade stores the colour of a
// fragment whose key is in a slot, and returns, to be blended in drawing order, the colour of one
// that is not (farther than the k nearest). The resolve composites the slots over the result.
struct KBuffer {
    width: u32,
    height: u32,
    k: u32,
    pad: u32,
};

@group(2) @binding(0) var<uniform> kbuffer: KBuffer;
@group(2) @binding(1) var<storage, read_write> kbuffer_keys: array<atomic<u32>>;
@group(2) @binding(2) var<storage, read_write> kbuffer_colours: array<u32>;
@group(2) @binding(3) var<storage, read_write> kbuffer_counts: array<atomic<u32>>;
@group(2) @binding(4) var kbuffer_opaque: texture_depth_multisampled_2d;

// The fragment's first slot, or none (clipped away, a closed organ's face turned away where no cut
// shows its inside, or behind the opaque organs at every sample). The passes write storage, so
// the depth test is done here, before anything is written.
fn kbuffer_slot(in: VsOut, front: bool) -> i32 {
    let organ = organs[in.organ];
    if (!front && (organ.id.y & CLOSED) != 0u && (organ.id.y & CAPPED) == 0u) || removed(in) {
        return -1;
    }
    let at = vec2<i32>(in.clip.xy);
    var farthest = 0.0;
    for (var s = 0; s < 4; s++) {
        farthest = max(farthest, textureLoad(kbuffer_opaque, at, s));
    }
    if in.clip.z >= farthest {
        return -1;
    }
    return i32((u32(at.y) * kbuffer.width + u32(at.x)) * kbuffer.k);
}

fn kbuffer_key(in: VsOut) -> u32 {
    return max(~bitcast<u32>(in.clip.z), 1u);
}

@fragment
fn fs_kbuffer_depth(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let first = kbuffer_slot(in, front);
    if first >= 0 {
        let at = vec2<u32>(in.clip.xy);
        atomicAdd(&kbuffer_counts[at.y * kbuffer.width + at.x], 1u);
        var key = kbuffer_key(in);
        for (var i = 0u; i < kbuffer.k; i++) {
            let old = atomicMax(&kbuffer_keys[u32(first) + i], key);
            if old == 0u {
                break;
            }
            key = min(old, key);
        }
    }
    return vec4<f32>(0.0);
}

@fragment
fn fs_kbuffer_shade(in: VsOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let first = kbuffer_slot(in, front);
    if first < 0 {
        return vec4<f32>(0.0);
    }
    let a = organs[in.organ].colour.a;
    let c = surface(in, front);
    let key = kbuffer_key(in);
    for (var i = 0u; i < kbuffer.k; i++) {
        let at = u32(first) + i;
        if atomicLoad(&kbuffer_keys[at]) == key {
            // Colour stored as the square root of linear light (more steps in the darks), 8 bits.
            kbuffer_colours[at] = pack4x8unorm(vec4<f32>(sqrt(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0))), a));
            return vec4<f32>(0.0);
        }
    }
    // Farther than the k nearest: blended in drawing order, back to front (premultiplied).
    return vec4<f32>(c * a, a);
}

@fragment
fn fs_pick(in: VsOut) -> @location(0) u32 {
    clip(in);
    return organs[in.organ].id.x;
}

@fragment
fn fs_mask(in: VsOut) -> @location(0) vec4<f32> {
    clip(in);
    return organs[in.organ].colour;
}

@fragment
fn fs_pick_instance(in: VsOut) -> @location(0) u32 {
    clip(in);
    return in.instance;
}
