// Per-frame camera and sizes, shared by every pass (docs/template-contract.md, "Interface").
AO_UBO(0) uniform AOFrame {
    mat4 view;        // world -> view
    mat4 proj;        // view -> clip
    mat4 inv_proj;    // clip -> view
    vec4 proj_info;   // view.xy = (ndc.xy * proj_info.xy + proj_info.zw) * z, view.z = -z
    vec4 uv_to_ndc;   // ndc.xy = uv * uv_to_ndc.xy + uv_to_ndc.zw (the y sign differs per API)
    vec4 full_size;   // output: w, h, 1/w, 1/h
    vec4 ao_size;     // AO pass: w, h, 1/w, 1/h
    vec4 clip;        // near, far, radius (world units), pixels per world unit at z = 1 at AO resolution
    ivec4 frame_index;// x = frame number, y = parity (0/1) for progressive halves, zw unused
} frame;
