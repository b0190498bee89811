#version 460
// The BRDF map under an environment (`light::sampling`, model.md §3.10): each pixel's radiance towards its view ω_r is
// the BRDF integrated against the environment, estimated from `n_brdf` samples drawn from the baked table's
// envelope and `n_env` drawn from the environment's luminance, combined by the balance heuristic (`n_floor` of the
// BRDF's samples cosine-weighted: a third strategy with a fixed count). Each strategy's points are a randomly
// shifted R2 sequence, its cells drawn by inverting 2D CDFs. The CPU twin is `light::sampling::Integrator::pass` (same
// names), which the exact reference runs with the exact BRDF. One invocation per pixel; a dispatch covers a band of
// rows.
#define NO_DERIVATIVES
#define BAKED
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#include "baked.glsl"
#include "env_map_push.glsl"

layout(local_size_x_id = SPEC_MAP_LOCAL_SIZE, local_size_y_id = SPEC_MAP_LOCAL_SIZE) in;
// Read and written: a dispatch adds its chunk of samples to what the earlier ones summed.
layout(set = 0, binding = BINDING_MAP_IMAGE, rgba32f) uniform image2D map_image;

// The distributions (`light::sampling::Distribution2D::gpu_words`): the marginal CDF's nv + 1 values, each row's
// conditional CDF's nu + 1, then each cell's density.
layout(std430, set = 0, binding = BINDING_TABLE_SAMPLING) readonly buffer TableSampling { float table_sampling[]; };
layout(std430, set = 0, binding = BINDING_ENV_SAMPLING) readonly buffer EnvSampling { float env_sampling[]; };
layout(std430, set = 0, binding = BINDING_ENV_RADIANCE) readonly buffer EnvRadiance { vec4 env_radiance[]; };

#include "env_sampling.glsl"
#include "map_view.glsl"

// The patch frame (z the normal) in the environment's (+y up), and back (`light::sampling::env_of_patch`).
vec3 env_of_patch(vec3 omega) { return vec3(omega.x, omega.z, -omega.y); }
vec3 patch_of_env(vec3 d) { return vec3(d.x, -d.z, d.y); }

// The environment's texel lighting from `d` (its frame: `EnvLight::texel_of`).
uint env_texel_of(vec3 d) {
    float azimuth = atan(d.x, d.z) - map.rotation;
    uint x = min(uint(fract(azimuth / (2.0 * PI) + 0.5) * float(map.env_width)), map.env_width - 1u);
    float elevation = asin(clamp(d.y, -1.0, 1.0));
    uint y = min(uint(max((0.5 - elevation / PI) * float(map.env_height), 0.0)), map.env_height - 1u);
    return y * map.env_width + x;
}

// A direction of the environment's frame drawn by luminance × solid angle at the point xi (`EnvLight::sample`).
vec3 env_sample(vec2 xi) {
    vec2 frac;
    uvec2 cell = sample_cell(false, map.env_width, map.env_height, xi, frac);
    float azimuth = ((float(cell.x) + frac.x) / float(map.env_width) - 0.5) * 2.0 * PI + map.rotation;
    float h = float(map.env_height);
    float top = sin(0.5 * PI - float(cell.y) / h * PI), bottom = sin(0.5 * PI - float(cell.y + 1u) / h * PI);
    float s = mix(top, bottom, frac.y);
    float c = sqrt(max(1.0 - s * s, 0.0));
    return vec3(c * sin(azimuth), s, c * cos(azimuth));
}

// The table proposal's density at (u, v): its texels' densities bilinearly, 0 beyond the edge
// (`TableProposal::density`).
float table_density(vec2 uv) {
    vec2 f = (uv - params.table_uv.xy) / params.table_w.z - 0.5;
    vec2 f0 = floor(f);
    vec2 t = f - f0;
    float d[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 at = ivec2(f0) + ivec2(k & 1, k >> 1);
        bool inside = all(greaterThanEqual(at, ivec2(0))) && at.x < int(map.nu) && at.y < int(map.nv);
        d[k] = inside ? cell_density(true, map.nu, map.nv, uint(at.y) * map.nu + uint(at.x)) : 0.0;
    }
    return mix(mix(d[0], d[1], t.x), mix(d[2], d[3], t.x), t.y);
}

// The BRDF strategies' densities in (u, v) for the view omega_r, each times its samples: the table's and the
// cosine-weighted floor's (`Integrator::brdf_density`).
float brdf_density(vec2 uv, vec3 omega_r) {
    vec2 xy = -uv - omega_r.xy;
    float disc = dot(xy, xy) < 1.0 ? 1.0 / PI : 0.0;
    return float(map.n_brdf - map.n_floor) * table_density(uv) + float(map.n_floor) * disc;
}

// One sample's contribution for light from omega_i (`Integrator::contribution`).
vec3 contribution(vec3 omega_i, vec3 omega_r) {
    uint texel = env_texel_of(env_of_patch(omega_i));
    vec3 radiance = env_radiance[texel].rgb;
    float p_env = cell_density(false, map.env_width, map.env_height, texel);
    float p_brdf = brdf_density(-omega_i.xy - omega_r.xy, omega_r);
    float denominator = p_brdf * omega_i.z + float(map.n_env) * p_env;
    if (!(denominator > 0.0) || all(equal(radiance, vec3(0.0)))) return vec3(0.0);
    vec3 rho = xyz_to_linear_srgb(baked_diffraction_xyz(omega_i, omega_r, 0.0));
    return rho * map.gain * radiance / params.light_white.rgb / denominator;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) + ivec2(map.origin);
    if (any(greaterThanEqual(pixel, imageSize(map_image)))) return;
    vec4 view = map_view(vec2(pixel) + 0.5, map.offset, map.size);
    if (view.w == 0.0) {
        imageStore(map_image, pixel, vec4(0.0, 0.0, 0.0, 1.0));
        return;
    }
    vec3 omega_r = view.xyz;
    // Each strategy's shift of the R2 sequence, hashed from the pixel and the seed.
    rng_state = pcg(uint(pixel.y) * 65536u + uint(pixel.x) ^ pcg(map.seed));
    uvec2 shifts[3];
    for (int s = 0; s < 3; ++s) shifts[s] = uvec2(next_uint(), next_uint());
    // This dispatch's chunk of each strategy's samples: k from map.first, map.chunk of them (a dispatch's loops stay
    // far below llvmpipe's 65535 iterations per invocation).
    vec3 total = map.first == 0u ? vec3(0.0) : imageLoad(map_image, pixel).rgb;
    uint n_table = map.n_brdf - map.n_floor;
    uint last = map.first + map.chunk;
    for (uint k = map.first; k < min(map.n_floor, last); ++k) {
        // Uniform over the unit disc of ω_i.xy.
        vec2 xi = r2(k, shifts[0]);
        vec2 ixy = sqrt(xi.x) * vec2(cos(2.0 * PI * xi.y), sin(2.0 * PI * xi.y));
        float i2 = dot(ixy, ixy);
        if (i2 < 1.0) total += contribution(vec3(ixy, sqrt(1.0 - i2)), omega_r);
    }
    for (uint k = map.first; k < min(n_table, last); ++k) {
        vec2 frac;
        uvec2 cell = sample_cell(true, map.nu, map.nv, r2(k, shifts[1]), frac);
        vec2 uv = params.table_uv.xy + (vec2(cell) + 0.5 + vec2(tent(frac.x), tent(frac.y))) * params.table_w.z;
        vec2 ixy = -uv - omega_r.xy;
        float i2 = dot(ixy, ixy);
        if (i2 < 1.0) total += contribution(vec3(ixy, sqrt(1.0 - i2)), omega_r);
    }
    for (uint k = map.first; k < min(map.n_env, last); ++k) {
        vec3 omega_i = patch_of_env(env_sample(r2(k, shifts[2])));
        if (omega_i.z > 0.0) total += contribution(omega_i, omega_r);
    }
    imageStore(map_image, pixel, vec4(total, 1.0));
}
