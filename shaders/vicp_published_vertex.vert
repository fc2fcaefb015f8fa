// VICP-VertexProg as Moreland's dissertation gives it (--interpolation gpu): the GLSL twin of
// gpu/vicp/vicp_published_vertex.cpp, operation for operation, every result `precise` (no fused multiply-add, no
// reordering). Read that file's header first. vicp_published.glsl (the struct, the view's uniforms, the dot product) is
// compiled in front of this file.

VicpPublishedVaryings vicp_published_vertex_program(vec3 position, float s, vec3 gradient, vec3 plane, float index)
{
    vec3 r = vicp_published_direction;
    if (vicp_published_orthographic == 0) {
        float vv = vicp_published_dot3(position, position);
        precise float rsq = inversesqrt(vv);  // 1 / sqrt(vv) on llvmpipe: two roundings
        precise vec3 rp = vec3(position.x * rsq, position.y * rsq, position.z * rsq);
        r = rp;
    }
    float nr = vicp_published_dot3(plane, r);
    precise float t = 1.0 / nr;
    float gr = vicp_published_dot3(gradient, r);
    precise float tg = t * gr;
    precise float s_exit = s + tg;
    VicpPublishedVaryings out_v;
    out_v.distance = vec3(0.0);
    out_v.scalar = vec3(s);
    out_v.s = s;
    int i = index == 0.0 ? 0 : index == 1.0 ? 1 : 2;
    out_v.distance[i] = t;
    out_v.scalar[i] = s_exit;
    return out_v;
}
