// The environment's diffraction, prefiltered (`env_prefilter`, model.md §3.11): the environment's radiance to l = 2
// as a quadratic form of the direction (frame.sky_quadratic: c₀, c, Q in the world), seen in the patch frame
// T = (x, y, normal) as L(ω) = Σ_j a_j m_j(ω) over the monomials (1, x, y, z, x², y², xy, xz, yz), integrated
// against the BRDF by its nine moments M_j(ω_r) (the material's moments texture: each a colour matrix from the
// light's RGB, upsampled in the spectral basis, to the reflected RGB), plus the specular reflectance times the
// environment's own radiance at the mirror direction (the quadratic's where the view has no map).
// Mirrors `Moments::radiance`.
// Requires surface_frame.glsl (frame), params.glsl, brdf.glsl.
#include "interface.glsl" // MOMENT_GRID, MOMENT_LAYERS

// 1 where the material has moments (`render::surface`); 0 compiles the term out.
layout(constant_id = SPEC_SKY_DIFFRACTION) const uint SKY_DIFFRACTION = 0;

layout(set = 0, binding = BINDING_MOMENTS) uniform sampler2DArray env_moments;
// The environment without its sun (`render::surface::EnvLighting`), equirectangular like the background's map:
// frame.sky_quadratic[1].w turns its texels into the frame's units, [2].w is its turn about +y, [3].w is 1 where
// the view has one (else the specular reflection reads the quadratic form).
layout(set = 0, binding = BINDING_ENV_LIGHT) uniform sampler2D env_light_map;

// The environment's radiance towards the world direction d, in the frame's units.
vec3 env_light_radiance(vec3 d) {
    float azimuth = atan(d.x, d.z) - frame.sky_quadratic[2].w;
    float elevation = asin(clamp(d.y, -1.0, 1.0));
    vec2 uv = vec2(azimuth / (2.0 * PI) + 0.5, 0.5 - elevation / PI);
    return textureLod(env_light_map, uv, 0.0).rgb * frame.sky_quadratic[1].w;
}

// The moments' grid coordinates of a view (`env_prefilter::grid_of_view`): the direction's azimuth at the radius
// θ_r/(π/2).
vec2 moment_grid_of_view(vec3 omega_r) {
    float s = length(omega_r.xy);
    if (s <= 0.0) return vec2(0.0);
    return omega_r.xy / s * (atan(s, omega_r.z) / (0.5 * PI));
}

// Moment j's colour matrix from the texture's scalars s (`Moments::gpu_texels`: 9j + 3c + r is row r of column c).
mat3 moment_matrix(float s[4 * MOMENT_LAYERS], int j) {
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

// The environment's diffracted radiance towards omega_r (patch frame) from the patch whose world axes are x, y and
// n: linear RGB in the environment's units; 0 where the frame does not diffract it.
vec3 sky_diffraction(vec3 omega_r, vec3 x, vec3 y, vec3 n) {
    if (SKY_DIFFRACTION == 0u || frame.sky_quadratic[0].w < 0.5 || omega_r.z <= 0.0) return vec3(0.0);
    vec3 a[9];
    sky_coefficients(x, y, n, a);
    // Texel centres at the grid's points.
    vec2 g = moment_grid_of_view(omega_r);
    vec2 uv = ((g + 1.0) * 0.5 * float(MOMENT_GRID - 1u) + 0.5) / float(MOMENT_GRID);
    float s[4 * MOMENT_LAYERS];
    for (uint l = 0u; l < MOMENT_LAYERS; ++l) {
        vec4 v = textureLod(env_moments, vec3(uv, float(l)), 0.0);
        s[4u * l] = v.x;
        s[4u * l + 1u] = v.y;
        s[4u * l + 2u] = v.z;
        s[4u * l + 3u] = v.w;
    }
    vec3 mirror = vec3(-omega_r.xy, omega_r.z);
    float m[9] = float[9](1.0, mirror.x, mirror.y, mirror.z, mirror.x * mirror.x, mirror.y * mirror.y,
                          mirror.x * mirror.y, mirror.x * mirror.z, mirror.y * mirror.z);
    vec3 diffracted = vec3(0.0), at_mirror = vec3(0.0);
    for (int j = 0; j < 9; ++j) {
        diffracted += moment_matrix(s, j) * a[j];
        at_mirror += a[j] * m[j];
    }
    mat3 specular = moment_matrix(s, 9);
    // The specular disc's light: the environment itself at the mirror direction where the view has it.
    if (frame.sky_quadratic[3].w > 0.5) at_mirror = env_light_radiance(mat3(x, y, n) * mirror);
    // The grid holds the moments over Schlick's R/R₀ at the mirror direction (`env_prefilter::mirror_fresnel`).
    float fresnel = fresnel_ratio(mirror, omega_r, SKIN_INDEX);
    return fresnel * (max(diffracted, vec3(0.0)) + specular * max(at_mirror, vec3(0.0)));
}
