#version 460
// A tiny compute kernel that the GPU tests use to prove compute pipelines, push descriptors, push constants
// and specialization constants work end to end: out[i] = SCALE * in[i]^2 + offset.
layout(local_size_x = 64) in;
layout(constant_id = 0) const float SCALE = 1.0;
layout(set = 0, binding = 0) readonly buffer Input { float values_in[]; };
layout(set = 0, binding = 1) writeonly buffer Output { float values_out[]; };
layout(push_constant) uniform Push { float offset; uint count; } pc;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= pc.count) return;
    values_out[i] = SCALE * values_in[i] * values_in[i] + pc.offset;
}
