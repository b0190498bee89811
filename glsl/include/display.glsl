// The display's encoding; mirrors physics::spectrum::display_encode (same names).

float srgb_oetf(float c) {
    c = clamp(c, 0.0, 1.0);
    return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

// Linear RGB -> display sRGB in [0, 1], after scaling by exposure_scale (2^EV, as the CPU twin
// physics::spectrum::display_encode takes it).
vec3 display_encode(vec3 linear_rgb, float exposure_scale) {
    vec3 c = linear_rgb * exposure_scale;
    return vec3(srgb_oetf(c.r), srgb_oetf(c.g), srgb_oetf(c.b));
}
