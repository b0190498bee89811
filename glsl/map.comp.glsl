#version 460
// The BRDF map as a compute shader, one invocation per pixel, written to a storage image: the same pixels as
// map.frag's (map_pixel.glsl), without the raster units: on an NVIDIA H200, a compute part with few of them, the
// Elaphe map's shading ran 9–41× faster so. A dispatch covers the rows from map.origin.y on (a band of them).
#define NO_DERIVATIVES
#include "params.glsl"
#include "spectrum.glsl"
#include "brdf.glsl"
#ifdef BAKED
#include "baked.glsl"
#else
#include "taylor.glsl"
#include "approaches.glsl"
#endif

#include "map_push.glsl"
#include "map_pixel.glsl"
layout(local_size_x_id = SPEC_MAP_LOCAL_SIZE, local_size_y_id = SPEC_MAP_LOCAL_SIZE) in;
layout(set = 0, binding = BINDING_MAP_IMAGE, rgba32f) uniform writeonly image2D map_image;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) + ivec2(map.origin);
    if (any(greaterThanEqual(pixel, imageSize(map_image)))) return;
    imageStore(map_image, pixel, map_pixel(vec2(pixel) + 0.5));
}
