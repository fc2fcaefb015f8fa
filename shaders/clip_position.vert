// The vertex stage's position, shared by HAVS (havs_vertex.vert) and VICP (vicp.vert): the GLSL twin of
// gpu/pipeline/clip_position.cpp clip_position and dp4_position (the paper's DP4 rows, for the HAVS paper's program).
// World position to clip coordinates with the model-view-projection matrix the CPU built in double and rounded to float
// once; each row as ((m0 * x + m1 * y) + m2 * z) + m3, every result `precise` so that no compiler fuses or reorders it.
// What the rasterizer does next (the draw module's viewport transform, snapping) is emulated in
// gpu/pipeline/rasterize.cpp.

// mvp is column-major, as Mat4f: mvp[c][r] is column c, row r.
float clip_row(mat4 mvp, vec3 p, int r)
{
    precise float acc = mvp[0][r] * p.x;
    acc = acc + mvp[1][r] * p.y;
    acc = acc + mvp[2][r] * p.z;
    acc = acc + mvp[3][r];
    return acc;
}

vec4 clip_position(mat4 mvp, vec3 p)
{
    return vec4(clip_row(mvp, p, 0), clip_row(mvp, p, 1), clip_row(mvp, p, 2), clip_row(mvp, p, 3));
}

// The paper's ARB program: DP4 with each row of m. GLSL's dot and ARB's DP4 are both NIR's fdot4, which llvmpipe sums
// from the last component down; p.w is the attribute's default 1 (a vec4 input fed three components).
vec4 dp4_position(mat4 m, vec4 p)
{
    precise vec4 c = vec4(dot(vec4(m[0][0], m[1][0], m[2][0], m[3][0]), p),
                          dot(vec4(m[0][1], m[1][1], m[2][1], m[3][1]), p),
                          dot(vec4(m[0][2], m[1][2], m[2][2], m[3][2]), p),
                          dot(vec4(m[0][3], m[1][3], m[2][3], m[3][3]), p));
    return c;
}
