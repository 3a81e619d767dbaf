// Appended to organ.wgsl, after `enable clip_distances;`, where the device has clip distances
// (see render::organ_source): vs_clipped is vs_main that also gives the rasteriser each plane's
// distance (world millimetres times the normal's length; negative is removed), so triangles are
// cut at the planes exactly and a triangle the planes remove draws no sample. Only organs the planes
// cut (CLIPPED) are cut; planes left unused (normal zero) keep everything. The fragment stage reads
// VsOut as from vs_main.

struct VsClipped {
    @builtin(position) clip: vec4<f32>,
    @location(0) world: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) @interpolate(flat) instance: u32,
    @location(3) @interpolate(flat) organ: u32,
    @location(4) @interpolate(flat) territory: u32,
    @builtin(clip_distances) distances: array<f32, 4>,
};

@vertex
fn vs_clipped(in: VsIn, @builtin(instance_index) instance: u32) -> VsClipped {
    let v = organ_vertex(in, instance);
    var out: VsClipped;
    out.clip = v.clip;
    out.world = v.world;
    out.normal = v.normal;
    out.instance = v.instance;
    out.organ = v.organ;
    out.territory = v.territory;
    let cut = (organs[in.organ].id.y & CLIPPED) != 0u;
    for (var k = 0; k < 4; k++) {
        let plane = frame.clip[k];
        let used = cut && any(plane.xyz != vec3<f32>(0.0));
        out.distances[k] = select(1.0, plane.w - dot(plane.xyz, v.world), used);
    }
    return out;
}
