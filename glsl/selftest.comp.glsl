#version 460
// A tiny compute kernel that the GPU tests use to prove compute pipelines, push descriptors, push constants
// and specialization constants work end to end: out[i] = SCALE * in[i]^2 + offset.
#include "interface.glsl"
layout(local_size_x = LOCAL_SIZE_X) in;
layout(constant_id = SPEC_SELFTEST_SCALE) const float SCALE = 1.0;
layout(set = 0, binding = BINDING_SELFTEST_IN) readonly buffer Input { float values_in[]; };
layout(set = 0, binding = BINDING_SELFTEST_OUT) writeonly buffer Output { float values_out[]; };
#include "selftest_push.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    values_out[i] = SCALE * values_in[i] * values_in[i] + pc.offset;
}
