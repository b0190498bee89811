// The numbers the shaders and the Rust side agree on (specialization ids, bindings, workgroup sizes): the same
// names and values as src/shaders/interface.rs, which build.rs compares with this file before compiling.
#ifndef INTERFACE_GLSL
#define INTERFACE_GLSL

// Specialization constants of the diffraction shaders (params.glsl).
#define SPEC_TERMS 0
#define SPEC_WINDOW_RADIUS 1
#define SPEC_LAMBDA_COUNT 2
#define SPEC_APPROACH 3
#define SPEC_DISPLAY_OUTPUT 4
#define SPEC_COUNT_STRIDE 5
#define SPEC_FOOTPRINT 8

// Specialization constants of single shaders.
#define SPEC_GBUFFER_PART 0
#define SPEC_PROBE_LAYERS 0
#define SPEC_PROBE_TAPS 1
#define SPEC_SELFTEST_SCALE 0

// Descriptor bindings (set 0).
#define BINDING_FRAME 0
#define BINDING_PARAMS 1
#define BINDING_TABLE 2
#define BINDING_SPECTRUM 3
#define BINDING_FETCH_COUNTS 4
#define BINDING_QUERIES 5
#define BINDING_RESULTS 6
#define BINDING_SELFTEST_IN 0
#define BINDING_SELFTEST_OUT 1

// Workgroup sizes.
#define LOCAL_SIZE_X 64

#endif
