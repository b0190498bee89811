// The skin's pigment under the grating and its sky light (`physics::optics`, `physics::sh`: their twins, same
// names; ARCHITECTURE.md, "Twins"). Needs brdf.glsl (fresnel_reflectance) and `frame` (surface_frame.glsl) declared
// before it.

// SUN_SOLID_ANGLE (interface.glsl): the sun's solid angle (0.53° across), sr, its diffuse contribution relative to
// its glint in a mirror.

// The share of light that crosses the skin's surface at incidence cos θ: 1 − R, exact Fresnel
// (`optics::transmittance`).
float transmittance(float cos_theta) {
    return 1.0 - fresnel_reflectance(cos_theta, SKIN_INDEX);
}

// The same averaged over a uniform sky's incidences (cosine-weighted; SKY_TRANSMITTANCE, interface.glsl).
float sky_transmittance() {
    return SKY_TRANSMITTANCE;
}

// The light the skin's pigment returns under the grating, linear RGB; mirrors `optics::pigment_rgb` (the
// profiler's reference adds it on the CPU). A Lambertian `albedo` under the skin's surface, lit through that
// surface by the sun's disc (cos θ_i, times the share `sun_visible` of it that no shadow hides) and by a sky of
// radiance `ambient` above the horizon with dark ground below (a surface whose normal makes cos = `normal_up` with
// the world's up sees (1 + normal_up)/2 of it), and seen through it. A matte surface (`coated` false) has no skin:
// the albedo is lit and seen directly.
vec3 pigment_rgb(vec3 omega_i, vec3 omega_r, float normal_up, vec3 albedo, float ambient, float sun_visible,
                 bool coated) {
    if (omega_r.z <= 0.0) return vec3(0.0);
    float sun = SUN_SOLID_ANGLE / PI * max(omega_i.z, 0.0) * sun_visible * (coated ? transmittance(omega_i.z) : 1.0);
    float sky = ambient * 0.5 * (1.0 + normal_up) * (coated ? sky_transmittance() : 1.0);
    return albedo * ((coated ? transmittance(omega_r.z) : 1.0) * (sun + sky));
}

// The environment's irradiance over π at the world normal `n`: the sum of its nine SH coefficients
// (`physics::sh::Irradiance::over_pi`), never negative; zero where the scene has no environment.
vec3 sky_over_pi(vec3 n) {
    vec3 e = frame.sky_sh[0].rgb * SH_Y00 + frame.sky_sh[1].rgb * (SH_Y1 * n.y)
        + frame.sky_sh[2].rgb * (SH_Y1 * n.z) + frame.sky_sh[3].rgb * (SH_Y1 * n.x)
        + frame.sky_sh[4].rgb * (SH_Y2 * n.x * n.y) + frame.sky_sh[5].rgb * (SH_Y2 * n.y * n.z)
        + frame.sky_sh[6].rgb * (SH_Y20 * (3.0 * n.z * n.z - 1.0)) + frame.sky_sh[7].rgb * (SH_Y2 * n.x * n.z)
        + frame.sky_sh[8].rgb * (SH_Y22 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// The pigment lit by the environment (`optics::pigment_sky_rgb`): through the skin both ways (unless matte), in
// the environment's own colours (not the illuminant's white).
vec3 pigment_sky_rgb(vec3 omega_r, vec3 albedo, vec3 sky, bool coated) {
    if (omega_r.z <= 0.0) return vec3(0.0);
    return albedo * (coated ? transmittance(omega_r.z) * sky_transmittance() : 1.0) * sky;
}
