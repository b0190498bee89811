// Spectral integration into colour; mirrors src/physics/spectrum.rs (same names).

const float TABLE_LAMBDA_MIN_NM = 380.0;
const float TABLE_LAMBDA_MAX_NM = 780.0;
const int TABLE_ROWS = 401;

// (x̄, ȳ, z̄, S/100) at lambda_nm, linearly interpolated; zero outside the tables.
vec4 spectrum_at(float lambda_nm) {
    if (lambda_nm < TABLE_LAMBDA_MIN_NM || lambda_nm > TABLE_LAMBDA_MAX_NM) return vec4(0.0);
    float x = lambda_nm - TABLE_LAMBDA_MIN_NM;
    int i = min(int(floor(x)), TABLE_ROWS - 2);
    return mix(spectrum_table[i], spectrum_table[i + 1], x - float(i));
}

// XYZ -> linear sRGB (IEC 61966-2-1); GLSL matrices are built from columns.
const mat3 XYZ_TO_LINEAR_SRGB = mat3(
    3.2404542, -0.9692660, 0.0556434,
    -1.5371385, 1.8760108, -0.2040259,
    -0.4985314, 0.0415560, 1.0572252);

vec3 xyz_to_linear_srgb(vec3 xyz) {
    return XYZ_TO_LINEAR_SRGB * xyz;
}

#include "display.glsl"
