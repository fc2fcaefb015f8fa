// VICP's vertex stage (Moreland's dissertation, VICP-VertexProg): the GLSL twin of gpu/vicp/vicp_vertex.cpp, operation
// for operation. Read that file's header first; the comments here only say where GLSL needs care. vicp_tet.glsl is
// compiled in front of this file; a pass appends its own main (vicp.vert in the renderer, vicp_harness.vert in the
// stage harness).
//
// Every arithmetic result is `precise` (no fused multiply-add, no reassociation), in double (GLSL fp64: IEEE double
// operations on llvmpipe; its draw module runs vertex shaders with denormals flushed, as its fragment threads).

dvec3 vicp_sub(dvec3 a, dvec3 b)
{
    precise dvec3 r = dvec3(a.x - b.x, a.y - b.y, a.z - b.z);
    return r;
}

dvec3 vicp_cross(dvec3 a, dvec3 b)
{
    precise double x = a.y * b.z - a.z * b.y;
    precise double y = a.z * b.x - a.x * b.z;
    precise double z = a.x * b.y - a.y * b.x;
    return dvec3(x, y, z);
}

// lambda_1..3's gradients n_i / det into m[0..2]; returns det.
double vicp_barycentric_gradients(dvec3 p[4], out dvec3 m[3])
{
    dvec3 e1 = vicp_sub(p[1], p[0]), e2 = vicp_sub(p[2], p[0]), e3 = vicp_sub(p[3], p[0]);
    dvec3 n1 = vicp_cross(e2, e3), n2 = vicp_cross(e3, e1), n3 = vicp_cross(e1, e2);
    precise double det = (e1.x * n1.x + e1.y * n1.y) + e1.z * n1.z;
    precise double inv = 1.0lf / det;
    precise dvec3 m0 = dvec3(n1.x * inv, n1.y * inv, n1.z * inv);
    precise dvec3 m1 = dvec3(n2.x * inv, n2.y * inv, n2.z * inv);
    precise dvec3 m2 = dvec3(n3.x * inv, n3.y * inv, n3.z * inv);
    m[0] = m0;
    m[1] = m1;
    m[2] = m2;
    return det;
}

VicpTet vicp_tet_constants(dvec3 shape[4], dvec3 exact[4], double s[4], uint boundary)
{
    VicpTet t;
    t.p0 = shape[0];
    t.det = vicp_barycentric_gradients(shape, t.m);
    vicp_barycentric_gradients(exact, t.me);
    t.boundary = boundary;
    precise double d1 = s[1] - s[0];
    precise double d2 = s[2] - s[0];
    precise double d3 = s[3] - s[0];
    precise double gx = (d1 * t.me[0].x + d2 * t.me[1].x) + d3 * t.me[2].x;
    precise double gy = (d1 * t.me[0].y + d2 * t.me[1].y) + d3 * t.me[2].y;
    precise double gz = (d1 * t.me[0].z + d2 * t.me[1].z) + d3 * t.me[2].z;
    t.g = dvec3(gx, gy, gz);
    t.base = exact[0];
    t.s0 = s[0];
    return t;
}
