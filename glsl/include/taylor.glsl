// The Taylor sum P = Σ_taps g · Σ_n c_n F_n[tap], c_n = (k w)^n / n!; mirrors src/physics/exact.rs
// (`taylor_sum`, `taylor_sum_f32`) and src/physics/coherence.rs (taps: the nearest bin floor(s + 0.5) and
// WINDOW_RADIUS bins either side; bins beyond Nyquist contribute nothing).

vec2 cmul(vec2 a, vec2 b) {
    return vec2(a.x * b.x - a.y * b.y, a.x * b.y + a.y * b.x);
}

// Whether the frequency lies inside the band the height field samples.
bool in_band(vec2 s) {
    return abs(s.x) <= 0.5 * float(params.patch_px.x) && abs(s.y) <= 0.5 * float(params.patch_px.y);
}

// Coefficients c_n = (k w)^n / n!, built incrementally as the thesis does.
void taylor_coefficients(float kw, out float c[TERMS]) {
    c[0] = 1.0;
    for (uint n = 1u; n < TERMS; ++n) c[n] = c[n - 1u] * kw / float(n);
}

// Σ_n c_n F_n at one texel.
vec2 taylor_series_at(ivec2 texel, float c[TERMS]) {
    vec2 acc = vec2(0.0);
    for (uint n = 0u; n < TERMS; ++n) acc += c[n] * texelFetch(taylor_terms, ivec3(texel, int(n)), 0).rg;
#ifdef COUNT_FETCHES
    fetch_count += TERMS;
#endif
    return acc;
}

// The exact DTFT kernel of an n-sample patch, (1/n) Σ_x e^{2πi d x/n} = e^{iπd(n−1)/n} sin(πd) / (n sin(πd/n)):
// sinc reconstruction of the single patch's spectrum from its bins (model.md §1.12, with the kernel's
// argument in bins, not in units of σ_f: §7.2 item 4).
vec2 dtft_kernel(float d, int n) {
    float a = PI * d;
    float den = float(n) * sin(a / float(n));
    float magnitude = abs(den) < 1e-6 ? 1.0 : sin(a) / den;
    float phase = a * float(n - 1) / float(n);
    return magnitude * vec2(cos(phase), sin(phase));
}

// The complex weight of bin j for a lookup at s: the Gaussian coherence window (1 at a bin centre), or for PQ
// the single patch's DTFT kernel.
vec2 tap_weight(vec2 s, ivec2 j) {
    if (APPROACH == APPROACH_PQ) {
        return cmul(dtft_kernel(s.x - float(j.x), params.patch_px.x), dtft_kernel(s.y - float(j.y), params.patch_px.y));
    }
    vec2 e = (vec2(j) - s) / params.window.xy;
    return vec2(exp(-0.5 * dot(e, e)), 0.0);
}

// The windowed amplitude at fractional bin position s (relative to DC) for k·w = kw (1/µm).
vec2 taylor_sum(vec2 s, float kw) {
    float c[TERMS];
    taylor_coefficients(kw, c);
    ivec2 n = params.patch_px.xy;
    ivec2 half_n = n / 2;
    ivec2 nearest = ivec2(floor(s + 0.5));
    vec2 p = vec2(0.0);
    for (int dy = -WINDOW_RADIUS; dy <= WINDOW_RADIUS; ++dy) {
        for (int dx = -WINDOW_RADIUS; dx <= WINDOW_RADIUS; ++dx) {
            ivec2 j = nearest + ivec2(dx, dy);
            ivec2 texel = j + half_n;
            if (any(lessThan(texel, ivec2(0))) || any(greaterThanEqual(texel, n))) continue;
            p += cmul(tap_weight(s, j), taylor_series_at(texel, c));
        }
    }
    return p;
}

// |Σ_{m<P} e^{2πi s m}|² / P²: the intensity factor of P periodic copies of the patch along one axis
// (model.md §1.11 with its sign and 2D-combination errors fixed: the 2D factor is the product of the axes').
float periodic_gain(float s, float periods) {
    float t = s - floor(s + 0.5);
    float den = sin(PI * t);
    if (abs(den) < 1e-6) return 1.0;
    float num = sin(PI * periods * t);
    return num * num / (periods * periods * den * den);
}
