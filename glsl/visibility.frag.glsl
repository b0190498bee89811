#version 460
// The visibility buffer's raster pass (`render::visibility`): each sample keeps which object's triangle it sees,
// ((object + 1) << VISIBILITY_OBJECT_SHIFT) | the triangle's index, and nothing else. The depth test (GREATER,
// written: depth is reversed) runs before this shader, so a hidden triangle never writes.
#include "interface.glsl"
#include "visibility_push.glsl"

layout(early_fragment_tests) in;

layout(location = 0) out uint out_id;

void main() {
    out_id = (visibility.object << VISIBILITY_OBJECT_SHIFT) | uint(gl_PrimitiveID);
}
