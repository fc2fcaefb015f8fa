// What VICP's published programs share on both sides of the rasterizer (--interpolation gpu): the varyings' struct, the
// view (VicpPublishedView of gpu/vicp/vicp_published_vertex.h), the dot product in the emulation's order, and the
// ordering-error diagnostic's entry distance. The GLSL twin of those parts of gpu/vicp/vicp_published_vertex.cpp;
// compiled in front of vicp_published_vertex.vert and of the draw's vicp_published.frag.

struct VicpPublishedVaryings {
    vec3 distance;
    vec3 scalar;
    float s;
};

uniform int vicp_published_orthographic;  // VicpPublishedView
uniform vec3 vicp_published_direction;

// ((a.z b.z + a.y b.y) + a.x b.x), as the emulation's vicp_published_dot3.
float vicp_published_dot3(vec3 a, vec3 b)
{
    precise float zz = a.z * b.z;
    precise float yy = a.y * b.y;
    precise float xx = a.x * b.x;
    precise float zy = zz + yy;
    precise float d = zy + xx;
    return d;
}

// vicp_published_entry_distance: the interpolated entry point's distance along the view ray (not the published: uvr's
// ordering-error diagnostic).
float vicp_published_entry_distance(vec3 entry)
{
    if (vicp_published_orthographic != 0) return vicp_published_dot3(entry, vicp_published_direction);
    precise float d = sqrt(vicp_published_dot3(entry, entry));
    return d;
}
