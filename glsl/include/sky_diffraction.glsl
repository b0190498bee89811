// The environment's diffraction, prefiltered (`light::prefilter`, model.md §3.11): the environment's radiance to l = 2
// as a quadratic form of the direction (frame.sky_quadratic: c₀, c, Q in the world), seen in the patch frame
// T = (x, y, normal) as L(ω) = Σ_j a_j m_j(ω) over the monomials (1, x, y, z, x², y², xy, xz, yz), integrated
// against the BRDF by its nine moments M_j(ω_r) (the material's moments texture: each a colour matrix from the
// light's RGB, upsampled in the spectral basis, to the reflected RGB), plus the specular reflectance times the
// environment's own radiance at the mirror direction (the quadratic's where the view has no map).
// Mirrors `Moments::radiance`. With SKY_DIFFRACTION_VERTEX the diffracted part (nine of the ten moments, 21 of the
// 23 layers) is evaluated at the vertices (surface.vert built with SKY_DIFFRACTION_AT_VERTEX) and interpolated:
// against a quadratic light it is broad and changes slowly with the view. The specular part stays per pixel: the
// structure's coherent reflectance changes colour quickly with the angle, and a map's light is sharp.
// Requires surface_frame.glsl (frame) and brdf.glsl.
#include "interface.glsl" // MOMENT_GRID, MOMENT_LAYERS, PI, SKY_DIFFRACTION_*
#include "panorama.glsl"  // panorama_uv

// Where the material's moments are read (`render::scene_gpu::MaterialGpu`): SKY_DIFFRACTION_NONE compiles the term out.
layout(constant_id = SPEC_SKY_DIFFRACTION) const uint SKY_DIFFRACTION = SKY_DIFFRACTION_NONE;

layout(set = 0, binding = BINDING_MOMENTS) uniform sampler2DArray env_moments;

// The moments' grid coordinates of a view (`light::prefilter::grid_of_view`): the direction's azimuth at the radius
// θ_r/(π/2).
vec2 moment_grid_of_view(vec3 omega_r) {
    float s = length(omega_r.xy);
    if (s <= 0.0) return vec2(0.0);
    return omega_r.xy / s * (atan(s, omega_r.z) / (0.5 * PI));
}

// The moments texture's coordinates of a view: texel centres at the grid's points.
vec2 moment_uv(vec3 omega_r) {
    vec2 g = moment_grid_of_view(omega_r);
    return ((g + 1.0) * 0.5 * float(MOMENT_GRID - 1u) + 0.5) / float(MOMENT_GRID);
}

// Layers holding the nine diffraction moments (scalars 0..80); the specular one's (81..89) are layers 20..22.
const uint DIFFRACTED_LAYERS = 21u;

// Moment j's colour matrix from the texture's scalars s (`Moments::gpu_texels`: 9j + 3c + r is row r of column c).
mat3 moment_matrix(float s[4 * DIFFRACTED_LAYERS], int j) {
    int o = 9 * j;
    return mat3(s[o], s[o + 1], s[o + 2], s[o + 3], s[o + 4], s[o + 5], s[o + 6], s[o + 7], s[o + 8]);
}

// The quadratic's coefficients a_j in the patch frame whose world axes are x, y, n (`Quadratic::coefficients`).
void sky_coefficients(vec3 x, vec3 y, vec3 n, out vec3 a[9]) {
    mat3 t = mat3(x, y, n);
    vec3 c[3] = vec3[3](frame.sky_quadratic[1].rgb, frame.sky_quadratic[2].rgb, frame.sky_quadratic[3].rgb);
    vec3 q[3][3];
    q[0][0] = frame.sky_quadratic[4].rgb;
    q[1][1] = frame.sky_quadratic[5].rgb;
    q[2][2] = frame.sky_quadratic[6].rgb;
    q[0][1] = frame.sky_quadratic[7].rgb;
    q[1][0] = q[0][1];
    q[0][2] = frame.sky_quadratic[8].rgb;
    q[2][0] = q[0][2];
    q[1][2] = frame.sky_quadratic[9].rgb;
    q[2][1] = q[1][2];
    // c' = Tᵀc and Q' = TᵀQT, channel by channel (t[i] is the patch's axis i in the world).
    vec3 cp[3];
    vec3 qp[3][3];
    for (int i = 0; i < 3; ++i) {
        cp[i] = c[0] * t[i].x + c[1] * t[i].y + c[2] * t[i].z;
        for (int j = 0; j < 3; ++j) {
            vec3 qt = vec3(0.0);
            for (int k = 0; k < 3; ++k) qt += t[i][k] * (q[k][0] * t[j].x + q[k][1] * t[j].y + q[k][2] * t[j].z);
            qp[i][j] = qt;
        }
    }
    a[0] = frame.sky_quadratic[0].rgb + qp[2][2];
    a[1] = cp[0];
    a[2] = cp[1];
    a[3] = cp[2];
    a[4] = qp[0][0] - qp[2][2];
    a[5] = qp[1][1] - qp[2][2];
    a[6] = 2.0 * qp[0][1];
    a[7] = 2.0 * qp[0][2];
    a[8] = 2.0 * qp[1][2];
}

// Whether the frame diffracts the environment towards omega_r at all.
bool sky_diffracts(vec3 omega_r) {
    return frame.sky_quadratic[0].w > 0.5 && omega_r.z > 0.0;
}

// The environment's light diffracted away from the mirror direction towards omega_r (patch frame) from the patch
// whose world axes are x, y and n: Σ_j N_j(ω_r) a_j over the nine moments, times Fresnel's R/R₀ at the mirror
// (the grid holds the moments over it: `light::prefilter::mirror_fresnel`); linear RGB in the environment's units.
vec3 sky_diffracted(vec3 omega_r, vec3 x, vec3 y, vec3 n) {
    if (!sky_diffracts(omega_r)) return vec3(0.0);
    vec3 a[9];
    sky_coefficients(x, y, n, a);
    vec2 uv = moment_uv(omega_r);
    float s[4 * DIFFRACTED_LAYERS];
    for (uint l = 0u; l < DIFFRACTED_LAYERS; ++l) {
        vec4 v = textureLod(env_moments, vec3(uv, float(l)), 0.0);
        s[4u * l] = v.x;
        s[4u * l + 1u] = v.y;
        s[4u * l + 2u] = v.z;
        s[4u * l + 3u] = v.w;
    }
    vec3 diffracted = vec3(0.0);
    for (int j = 0; j < 9; ++j) diffracted += moment_matrix(s, j) * a[j];
    vec3 mirror = vec3(-omega_r.xy, omega_r.z);
    return fresnel_ratio(mirror, omega_r, SKIN_INDEX) * max(diffracted, vec3(0.0));
}

#ifndef SKY_DIFFRACTION_AT_VERTEX
// The environment without its sun (`render::scene_gpu`'s `EnvLighting`), equirectangular like the background's map:
// frame.sky_quadratic[1].w turns its texels into the frame's units, [2].w is its turn about +y, [3].w is 1 where
// the view has one (else the specular reflection reads the quadratic form).
layout(set = 0, binding = BINDING_ENV_LIGHT) uniform sampler2D env_light_map;

// The environment's radiance towards the world direction d, in the frame's units: its map where the view has one,
// else its quadratic form (`Quadratic::radiance`).
vec3 env_light_radiance(vec3 d) {
    if (frame.sky_quadratic[3].w > 0.5) {
        return textureLod(env_light_map, panorama_uv(d, frame.sky_quadratic[2].w), 0.0).rgb * frame.sky_quadratic[1].w;
    }
    vec3 q = frame.sky_quadratic[4].rgb * (d.x * d.x) + frame.sky_quadratic[5].rgb * (d.y * d.y)
        + frame.sky_quadratic[6].rgb * (d.z * d.z)
        + 2.0 * (frame.sky_quadratic[7].rgb * (d.x * d.y) + frame.sky_quadratic[8].rgb * (d.x * d.z)
                 + frame.sky_quadratic[9].rgb * (d.y * d.z));
    return frame.sky_quadratic[0].rgb + frame.sky_quadratic[1].rgb * d.x + frame.sky_quadratic[2].rgb * d.y
        + frame.sky_quadratic[3].rgb * d.z + q;
}

// The specular disc's light towards omega_r: the specular moment (a colour matrix) times the environment itself
// at the mirror direction, times Fresnel's R/R₀ there.
vec3 sky_specular(vec3 omega_r, vec3 x, vec3 y, vec3 n) {
    vec2 uv = moment_uv(omega_r);
    // Scalars 81..89: the last three of layer 20, all of 21, the first two of 22.
    vec4 l20 = textureLod(env_moments, vec3(uv, 20.0), 0.0);
    vec4 l21 = textureLod(env_moments, vec3(uv, 21.0), 0.0);
    vec4 l22 = textureLod(env_moments, vec3(uv, 22.0), 0.0);
    mat3 specular = mat3(l20.yzw, l21.xyz, vec3(l21.w, l22.xy));
    vec3 mirror = vec3(-omega_r.xy, omega_r.z);
    vec3 at_mirror = max(env_light_radiance(mat3(x, y, n) * mirror), vec3(0.0));
    return fresnel_ratio(mirror, omega_r, SKIN_INDEX) * (specular * at_mirror);
}

// The environment's diffracted radiance towards omega_r (patch frame) from the patch whose world axes are x, y and
// n: linear RGB in the environment's units; 0 where the frame does not diffract it. With SKY_DIFFRACTION_VERTEX
// the diffracted part comes interpolated from the vertices (`vertex_diffracted`).
vec3 sky_diffraction(vec3 omega_r, vec3 x, vec3 y, vec3 n, vec3 vertex_diffracted) {
    if (SKY_DIFFRACTION == SKY_DIFFRACTION_NONE || !sky_diffracts(omega_r)) return vec3(0.0);
    vec3 diffracted = SKY_DIFFRACTION == SKY_DIFFRACTION_PIXEL ? sky_diffracted(omega_r, x, y, n) : vertex_diffracted;
    return diffracted + sky_specular(omega_r, x, y, n);
}
#endif
