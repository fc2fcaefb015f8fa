// What VICP's seed programs share on both sides of the rasterizer (--interpolation gpu): the varyings' struct, the
// view (VicpSeedView of gpu/vicp/vicp_seed_vertex.h), the dot product in the emulation's order, and the
// ordering-error diagnostic's entry distance. The GLSL twin of those parts of gpu/vicp/vicp_seed_vertex.cpp;
// compiled in front of vicp_seed_vertex.vert and of the draw's vicp_seed.frag.

struct VicpSeedVaryings {
    vec3 distance;
    vec3 scalar;
    float s;
};

uniform int vicp_seed_orthographic;  // VicpSeedView
uniform vec3 vicp_seed_direction;

// ((a.z b.z + a.y b.y) + a.x b.x), as the emulation's vicp_seed_dot3.
float vicp_seed_dot3(vec3 a, vec3 b)
{
    precise float zz = a.z * b.z;
    precise float yy = a.y * b.y;
    precise float xx = a.x * b.x;
    precise float zy = zz + yy;
    precise float d = zy + xx;
    return d;
}

// vicp_seed_entry_distance: the interpolated entry point's distance along the view ray (not the seed's: uvr's
// ordering-error diagnostic).
float vicp_seed_entry_distance(vec3 entry)
{
    if (vicp_seed_orthographic != 0) return vicp_seed_dot3(entry, vicp_seed_direction);
    precise float d = sqrt(vicp_seed_dot3(entry, entry));
    return d;
}
