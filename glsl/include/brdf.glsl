// Geometric factors of Stam's BRDF in the patch frame; mirrors src/physics/optics.rs (same names).

#include "interface.glsl" // SKIN_INDEX

// Fresnel's reflectance of unpolarised light from air at incidence cos θ on a dielectric of index n, exact: the
// mean of the s and p reflectances (`optics::fresnel_reflectance`).
float fresnel_reflectance(float cos_theta, float n) {
    float c = clamp(cos_theta, 0.0, 1.0);
    float cos_t = sqrt(1.0 - (1.0 - c * c) / (n * n));
    float rs = (c - n * cos_t) / (c + n * cos_t);
    float rp = (n * c - cos_t) / (n * c + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

// R(θ)/R0 with cos θ = H·ω_r, unsquared (model.md §7.2 item 2).
float fresnel_ratio(vec3 omega_i, vec3 omega_r, float n) {
    vec3 h = normalize(omega_i + omega_r);
    float r0 = (n - 1.0) * (n - 1.0) / ((n + 1.0) * (n + 1.0));
    return fresnel_reflectance(dot(h, omega_r), n) / r0;
}

// C(ω_i, ω_r) = (R/R0)·(1 + ω_i·ω_r)² / (cos θ_r · w²): |P|² -> relative reflectance (model.md §1.5).
float gain_factor(vec3 omega_i, vec3 omega_r) {
    if (omega_i.z <= 0.0 || omega_r.z <= 0.0) return 0.0;
    float w = -(omega_i.z + omega_r.z);
    float cos_sum = 1.0 + dot(omega_i, omega_r);
    return fresnel_ratio(omega_i, omega_r, SKIN_INDEX) * cos_sum * cos_sum / (omega_r.z * w * w);
}

// V-groove shadowing and masking with n = z (the patch frame, not the world normal: model.md §7.2 item 10).
float shadow_mask(vec3 omega_i, vec3 omega_r) {
    vec3 h = normalize(omega_i + omega_r);
    float eh = max(dot(omega_r, h), 1e-12);
    return clamp(min(2.0 * h.z * omega_r.z / eh, 2.0 * h.z * omega_i.z / eh), 0.0, 1.0);
}
