// The display's encoding; mirrors display::tone (same names and constants) and physics::spectrum::srgb_oetf.

float srgb_oetf(float c) {
    c = clamp(c, 0.0, 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// AgX (display::tone's `agx`): inset towards the achromatic axis, log₂ encoding over AGX_MIN_EV..AGX_MAX_EV, the
// sigmoid (a 7th-order fit, AGX_SIGMOID highest power first), outset; display values in [0, 1].
const mat3 AGX_INSET = mat3(0.842479062253094, 0.0423282422610123, 0.0423756549057051,
                            0.0784335999999992, 0.878468636469772, 0.0784336,
                            0.0792237451477643, 0.0791661274605434, 0.879142973793104);
const mat3 AGX_OUTSET = mat3(1.19687900512017, -0.0528968517574562, -0.0529716355144438,
                             -0.0980208811401368, 1.15190312990417, -0.0980434501171241,
                             -0.0990297440797205, -0.0989611768448433, 1.15107367264116);
const float AGX_MIN_EV = -12.47393;
const float AGX_MAX_EV = 4.026069;

vec3 agx(vec3 linear_rgb) {
    vec3 x = (clamp(log2(max(AGX_INSET * linear_rgb, vec3(1e-10))), AGX_MIN_EV, AGX_MAX_EV) - AGX_MIN_EV)
        / (AGX_MAX_EV - AGX_MIN_EV);
    vec3 y = ((((((-17.86 * x + 78.01) * x - 126.7) * x + 92.06) * x - 28.72) * x + 4.361) * x - 0.1718) * x
        + 0.002857;
    return clamp(AGX_OUTSET * y, 0.0, 1.0);
}

// Linear RGB -> display sRGB in [0, 1], after scaling by exposure_scale (2^EV) and the tone curve `tone`
// (display::Tone::gpu: 0 clip, 1 filmic), as the CPU twin display::tone::encode takes them.
vec3 display_encode(vec3 linear_rgb, float exposure_scale, float tone) {
    vec3 c = linear_rgb * exposure_scale;
    if (tone > 0.5) return agx(c);
    return vec3(srgb_oetf(c.r), srgb_oetf(c.g), srgb_oetf(c.b));
}
