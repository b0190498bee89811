// The shading approaches (model.md §3): each turns (u, v, w) into CIE XYZ relative to a D65 mirror (Y = 1).
// Requires params.glsl, spectrum.glsl, brdf.glsl and taylor.glsl.

// NMM falls back to uniform sampling where fewer bins than this are crossed (near specular, where the thesis
// drew a white disc instead).
const float NMM_MIN_SAMPLES = 4.0;
// Upper bound on NMM's per-axis loop (|u|·L/λ_min − |u|·L/λ_max bins; 2 × 65 µm patches need about 180).
const int NMM_MAX_SAMPLES = 4096;

// |P(λ)|² for the approach's reconstruction: Gaussian window, or PQ's DTFT kernel times the periodic factor.
float intensity_at(vec3 uvw, float lambda_nm) {
    float lambda_um = lambda_nm * 1e-3;
    vec2 s = uvw.xy * params.patch_um.xy / lambda_um;
    if (!in_band(s)) return 0.0;
    float kw = 2.0 * PI / lambda_um * uvw.z;
    vec2 p = taylor_sum(s, kw);
    float intensity = dot(p, p);
    if (APPROACH == APPROACH_PQ) intensity *= periodic_gain(s.x, params.pq.x) * periodic_gain(s.y, params.pq.y);
    return intensity;
}

// Uniform wavelength sampling (FLSS; PQ with its own intensity): X = Σ I x̄ S Δλ / Σ ȳ S Δλ.
vec3 flss_xyz(vec3 uvw) {
    vec3 xyz = vec3(0.0);
    for (uint k = 0u; k < LAMBDA_COUNT; ++k) {
        float lambda_nm = params.spectral.x + float(k) * params.spectral.y;
        vec4 cmf = spectrum_at(lambda_nm);
        if (cmf.w == 0.0) continue;
        xyz += intensity_at(uvw, lambda_nm) * cmf.xyz * cmf.w;
    }
    return xyz * params.spectral.y / params.spectral.z;
}

// One NMM axis: the wavelengths λ_n = t/n at which the lookup lands on bin n (t = |u|·L in nm), each weighted
// by its share of the λ axis, |dλ/dn| = λ²/t (the Jacobian the thesis left out).
vec3 nmm_axis(vec3 uvw, float t_nm) {
    vec3 xyz = vec3(0.0);
    float n_lo = max(ceil(t_nm / TABLE_LAMBDA_MAX_NM), 1.0);
    float n_hi = floor(t_nm / TABLE_LAMBDA_MIN_NM);
    for (int i = 0; i < NMM_MAX_SAMPLES; ++i) {
        float n = n_lo + float(i);
        if (n > n_hi) break;
        float lambda_nm = t_nm / n;
        vec4 cmf = spectrum_at(lambda_nm);
        xyz += intensity_at(uvw, lambda_nm) * cmf.xyz * cmf.w * (lambda_nm * lambda_nm / t_nm);
    }
    return xyz;
}

// NMM: both axes' estimates of the same integral, blended by how many bins each crosses (the thesis added
// them, counting the integral twice where both axes are active).
vec3 nmm_xyz(vec3 uvw) {
    vec2 t = abs(uvw.xy) * params.patch_um.xy * 1e3;
    vec2 crossed = floor(t / TABLE_LAMBDA_MIN_NM) - ceil(t / TABLE_LAMBDA_MAX_NM) + 1.0;
    if (max(crossed.x, crossed.y) < NMM_MIN_SAMPLES) return flss_xyz(uvw);
    float share_x = t.x / (t.x + t.y);
    vec3 xyz = vec3(0.0);
    if (crossed.x >= 1.0) xyz += share_x * nmm_axis(uvw, t.x);
    if (crossed.y >= 1.0) xyz += (1.0 - share_x) * nmm_axis(uvw, t.y);
    return xyz / params.spectral.w;
}

// Stam's analytic grating (GPU Gems ch. 8) with only the dominant spacing d: order m lies at λ_m = d·|a|/m,
// a coherence-limited line of integrated width √π·σ_f·λ_m²/|a| in λ (a, b = (u, v) along and across the grating),
// each non-zero order with the same efficiency; plus a white specular spot.
vec3 gem_xyz(vec3 uvw) {
    vec2 g = params.gem.xy;
    float d = params.gem.z;
    float sigma_f = params.window.z;
    float a = dot(uvw.xy, g);
    float b = dot(uvw.xy, vec2(-g.y, g.x));
    vec3 xyz = vec3(0.0);
    if (d > 0.0 && abs(a) > 1e-6) {
        float m_lo = max(ceil(d * abs(a) / (TABLE_LAMBDA_MAX_NM * 1e-3)), 1.0);
        float m_hi = floor(d * abs(a) / (TABLE_LAMBDA_MIN_NM * 1e-3));
        for (float m = m_lo; m <= m_hi; m += 1.0) {
            float lambda_um = d * abs(a) / m;
            vec4 cmf = spectrum_at(lambda_um * 1e3);
            float across = b / (lambda_um * sigma_f);
            float width_nm = sqrt(PI) * sigma_f * lambda_um * lambda_um / abs(a) * 1e3;
            xyz += params.gem.w * cmf.xyz * cmf.w * width_nm * exp(-across * across);
        }
        xyz /= params.spectral.w;
    }
    vec3 specular = vec3(0.0);
    float r2 = dot(uvw.xy, uvw.xy);
    for (uint k = 0u; k < LAMBDA_COUNT; ++k) {
        float lambda_nm = params.spectral.x + float(k) * params.spectral.y;
        float f = sqrt(r2) / (lambda_nm * 1e-3 * sigma_f);
        vec4 cmf = spectrum_at(lambda_nm);
        specular += exp(-f * f) * cmf.xyz * cmf.w;
    }
    return xyz + specular * params.spectral.y / params.spectral.z;
}

// The relative reflectance's colour for one pair of patch-frame directions: XYZ · C · shadowing.
vec3 diffraction_xyz(vec3 omega_i, vec3 omega_r) {
    if (omega_i.z <= 0.0 || omega_r.z <= 0.0) return vec3(0.0);
    vec3 uvw = -omega_i - omega_r;
    vec3 xyz;
    if (APPROACH == APPROACH_NMM) xyz = nmm_xyz(uvw);
    else if (APPROACH == APPROACH_GEM) xyz = gem_xyz(uvw);
    else xyz = flss_xyz(uvw);
    return xyz * gain_factor(omega_i, omega_r) * shadow_mask(omega_i, omega_r);
}

// The shader's output colour: linear scene-referred sRGB, or display sRGB after exposure. (light_white.w: the
// diffraction's gain, 1 in relative units, `spectrum::diffraction_gain`.)
vec3 shade(vec3 omega_i, vec3 omega_r) {
    vec3 rgb = xyz_to_linear_srgb(diffraction_xyz(omega_i, omega_r)) * params.light_white.w;
    return DISPLAY_OUTPUT == 1u ? display_encode(rgb, params.display.x, params.display.y) : rgb;
}
