// Organ shading: world-space vertices (model matrix applied here), headlight lighting.
// Entry points: vs_main (all organ pipelines), fs_shade (the "organ opaque" and "organ blend"
// pipelines), fs_pick (the "organ pick" pipeline writing organ IDs), fs_pick_instance (the
// "leaf pick" pipeline writing the instance index, which the benchmark sets to a leaf number).
// Keep in sync with FrameUniform and OrganUniform in src/render/renderer.rs.

struct Frame {
    view_proj: mat4x4<f32>,
    // Camera position in world space (w unused).
    eye: vec4<f32>,
};

struct Organ {
    // Organ space -> world space.
    model: mat4x4<f32>,
    // Inverse transpose of model's upper 3x3, as columns of a 4x4 (fourth unused).
    normal_matrix: mat4x4<f32>,
    // Linear RGB and opacity.
    colour: vec4<f32>,
    // x: organ index + 1 (0 = background in the ID buffer).
    id: vec4<u32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;
@group(1) @binding(0) var<uniform> organ: Organ;

struct VsIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
};

struct VsOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
};

@vertex
fn vs_main(in: VsIn, @builtin(instance_index) instance: u32) -> VsOut {
    var out: VsOut;
    out.instance = instance;
    let world = organ.model * vec4<f32>(in.position, 1.0);
    out.clip = frame.view_proj * world;
    out.world = world.xyz;
    out.normal = (organ.normal_matrix * vec4<f32>(in.normal, 0.0)).xyz;
    return out;
}

@fragment
fn fs_shade(in: VsOut) -> @location(0) vec4<f32> {
    // Headlight: the light sits at the eye. Two-sided, so cut-open or inner faces are lit too.
    let n = normalize(in.normal);
    let v = normalize(frame.eye.xyz - in.world);
    let ndl = abs(dot(n, v));
    let diffuse = organ.colour.rgb * (0.18 + 0.82 * ndl);
    let specular = vec3<f32>(0.18) * pow(ndl, 40.0);
    return vec4<f32>(diffuse + specular, organ.colour.a);
}

@fragment
fn fs_pick(in: VsOut) -> @location(0) u32 {
    return organ.id.x;
}

@fragment
fn fs_pick_instance(in: VsOut) -> @location(0) u32 {
    return in.instance;
}
