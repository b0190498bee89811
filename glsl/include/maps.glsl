// An object's surface maps (`scene::mesh::maps`, uploaded by `render::maps`): the pigment map (sRGB, filtered in
// linear light) multiplies the tint; the normal map (tangent space, OpenGL's convention: red along the mesh's
// tangent, green along its bitangent n × t) turns the surface's frame, so that the diffraction, the pigment, the
// sky and the lamps all see the mapped normal. Read with explicit gradients of the uv across and down a pixel (the
// forward pass's derivatives, the visibility pass's neighbouring pixels on the triangle). Requires surface_frame.glsl.

layout(set = 0, binding = BINDING_PIGMENT_MAP) uniform sampler2D pigment_map;
layout(set = 0, binding = BINDING_NORMAL_MAP) uniform sampler2D normal_map;

// 0 in the pipelines of a material none of whose objects has a map: the reads compile out.
layout(constant_id = SPEC_MAPS) const uint MAPS = 1;

// Whether the object has any map (a uniform: the branch is taken by every pixel alike).
bool has_maps() {
    return MAPS != 0u && frame.maps.x + frame.maps.y > 0.0;
}

// The maps applied at `uv` (its steps to the next pixel across, `dx`, and down, `dy`): the tint times the pigment
// map (where `pigment`), and the normal (world, `world_normal`) and the patch's x axis (`patch_axis`, its handedness in
// w) turned to the normal map's, with the sun's (`patch_light`) and the camera's (`patch_view`, from
// `world_position`) directions in the turned patch frame. The patch frame keeps its rotation about the normal (the
// material's orientation).
void apply_maps(vec2 uv, vec2 dx, vec2 dy, bool pigment, vec3 world_position, inout vec3 tint, inout vec3 patch_light,
                inout vec3 patch_view, inout vec3 world_normal, inout vec4 patch_axis) {
    if (pigment && frame.maps.x > 0.0) {
        tint *= textureGrad(pigment_map, uv, dx, dy).rgb;
    }
    if (frame.maps.y > 0.0) {
        vec3 m = textureGrad(normal_map, uv, dx, dy).rgb * 2.0 - 1.0;
        vec3 n = normalize(world_normal);
        vec3 px = normalize(patch_axis.xyz - n * dot(n, patch_axis.xyz));
        vec3 py = patch_axis.w * cross(n, px);
        // The mesh's tangent and bitangent: the patch's axes turned back by the material's orientation (surface.vert
        // turned them by (cos, sin) = frame.orientation.xy).
        vec2 o = frame.orientation.xy;
        vec3 t = o.x * px - o.y * py;
        vec3 b = o.y * px + o.x * py;
        vec3 mapped = normalize(m.x * t + m.y * b + max(m.z, 1e-3) * n);
        vec3 x = normalize(px - mapped * dot(mapped, px));
        vec3 y = patch_axis.w * cross(mapped, x);
        vec3 l = normalize(frame.light_dir.xyz);
        vec3 v = frame.camera_pos.xyz - world_position;
        patch_light = vec3(dot(l, x), dot(l, y), dot(l, mapped));
        patch_view = vec3(dot(v, x), dot(v, y), dot(v, mapped));
        world_normal = mapped;
        patch_axis.xyz = x;
    }
}
