// The interpolation stage's harness: the varyings as the rasterizer interpolated them, written as they are
// (RGBA32F targets), and the fragment's primitive, facing and gl_FragCoord.w.
smooth in vec4 v_smooth;
noperspective in vec4 v_noperspective;
flat in vec4 v_flat;

layout(location = 0) out vec4 o_smooth;
layout(location = 1) out vec4 o_noperspective;
layout(location = 2) out vec4 o_flat;
layout(location = 3) out vec4 o_info;

void main()
{
    o_smooth = v_smooth;
    o_noperspective = v_noperspective;
    o_flat = v_flat;
    o_info = vec4(float(gl_PrimitiveID), gl_FrontFacing ? 1.0 : 0.0, gl_FragCoord.w, 0.0);
}
