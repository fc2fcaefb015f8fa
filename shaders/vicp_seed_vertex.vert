// VICP-VertexProg as seed 003 gives it (--interpolation gpu): the GLSL twin of gpu/vicp/vicp_seed_vertex.cpp,
// operation for operation, every result `precise` (no fused multiply-add, no reordering). Read that file's header
// first. vicp_seed.glsl (the struct, the view's uniforms, the dot product) is compiled in front of this file.

VicpSeedVaryings vicp_seed_vertex_program(vec3 position, float s, vec3 gradient, vec3 plane, float index)
{
    vec3 r = vicp_seed_direction;
    if (vicp_seed_orthographic == 0) {
        float vv = vicp_seed_dot3(position, position);
        precise float rsq = inversesqrt(vv);  // 1 / sqrt(vv) on llvmpipe: two roundings
        precise vec3 rp = vec3(position.x * rsq, position.y * rsq, position.z * rsq);
        r = rp;
    }
    float nr = vicp_seed_dot3(plane, r);
    precise float t = 1.0 / nr;
    float gr = vicp_seed_dot3(gradient, r);
    precise float tg = t * gr;
    precise float s_exit = s + tg;
    VicpSeedVaryings out_v;
    out_v.distance = vec3(0.0);
    out_v.scalar = vec3(s);
    out_v.s = s;
    int i = index == 0.0 ? 0 : index == 1.0 ? 1 : 2;
    out_v.distance[i] = t;
    out_v.scalar[i] = s_exit;
    return out_v;
}
