// HAVS's vertex stage (seed 000, Appendix I): the GLSL twin of gpu/havs_vertex.cpp clip_position. World position to
// clip coordinates with the model-view-projection matrix the CPU built in double and rounded to float once; each row
// as ((m0 * x + m1 * y) + m2 * z) + m3, every result `precise` so that no compiler fuses or reorders it. What the
// rasterizer does next (the draw module's viewport transform, snapping) is emulated in gpu/rasterize.cpp.

layout(location = 0) in vec3 havs_position;
uniform mat4 havs_mvp;  // column-major, as Mat4f: havs_mvp[c][r] is column c, row r

float havs_clip_row(int r)
{
    precise float acc = havs_mvp[0][r] * havs_position.x;
    acc = acc + havs_mvp[1][r] * havs_position.y;
    acc = acc + havs_mvp[2][r] * havs_position.z;
    acc = acc + havs_mvp[3][r];
    return acc;
}

void main()
{
    gl_Position = vec4(havs_clip_row(0), havs_clip_row(1), havs_clip_row(2), havs_clip_row(3));
}
