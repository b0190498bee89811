// Spectral integration into colour; mirrors src/physics/spectrum.rs (same names). The tables' range and
// XYZ_TO_LINEAR_SRGB come from crates/gpu-interface (the library's gpu::interface).

#include "interface.glsl"

// (x̄, ȳ, z̄, S/100) at lambda_nm, linearly interpolated; zero outside the tables.
vec4 spectrum_at(float lambda_nm) {
    if (lambda_nm < TABLE_LAMBDA_MIN_NM || lambda_nm > TABLE_LAMBDA_MAX_NM) return vec4(0.0);
    float x = lambda_nm - TABLE_LAMBDA_MIN_NM;
    int i = min(int(floor(x)), TABLE_ROWS - 2);
    return mix(spectrum_table[i], spectrum_table[i + 1], x - float(i));
}

vec3 xyz_to_linear_srgb(vec3 xyz) {
    return XYZ_TO_LINEAR_SRGB * xyz;
}

#include "display.glsl"
