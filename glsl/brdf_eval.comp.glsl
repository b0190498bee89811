#version 460
// `diffract brdf --gpu`: power = |P|² of the Taylor sum and reflectance = C·power for a list of
// (ω_i, ω_r, λ), with the same include the fragment shaders use, so the GPU can be checked number for number.
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#include "taylor.glsl"

layout(local_size_x = LOCAL_SIZE_X) in;

struct BrdfQuery {
    vec4 omega_i_lambda;  // ω_i (patch frame), λ in nm
    vec4 omega_r;         // ω_r (patch frame), unused
};
layout(std430, set = 0, binding = BINDING_QUERIES) readonly buffer Queries { BrdfQuery queries[]; };
layout(std430, set = 0, binding = BINDING_RESULTS) writeonly buffer Results { vec2 results[]; };  // power, reflectance
#include "eval_push.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= eval.count) return;
    vec3 omega_i = queries[i].omega_i_lambda.xyz;
    vec3 omega_r = queries[i].omega_r.xyz;
    float lambda_um = queries[i].omega_i_lambda.w * 1e-3;
    vec3 uvw = -omega_i - omega_r;
    vec2 s = uvw.xy * params.patch_um.xy / lambda_um;
    float power = 0.0;
    if (in_band(s)) {
        vec2 p = taylor_sum(s, 2.0 * PI / lambda_um * uvw.z);
        power = dot(p, p);
    }
    results[i] = vec2(power, gain_factor(omega_i, omega_r) * power);
}
