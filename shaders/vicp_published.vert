// VICP's published program draw (--interpolation gpu, gpu/vicp/gl_vicp.cpp): the vertex program's main.
// clip_position.vert, vicp_published.glsl and vicp_published_vertex.vert are compiled in front of this file;
// vicp_published.frag is its fragment side. ProjectTet's records arrive as vertex attributes (VicpPublishedVertex, 11
// floats, twelve vertices a cell: face f's vertex j at 3 f + j), streamed in chunks; VertexProg's varyings leave
// `smooth`, as the published texture coordinates.
layout(location = 0) in vec3 vicp_published_position;  // relative to the eye
layout(location = 1) in float vicp_published_scalar_in;
layout(location = 2) in vec3 vicp_published_gradient;
layout(location = 3) in vec3 vicp_published_plane;
layout(location = 4) in float vicp_published_index;

uniform mat4 vicp_mvp;

smooth out vec3 vicp_published_distance;
smooth out vec3 vicp_published_scalar;
smooth out float vicp_published_s;
smooth out vec3 vicp_published_entry;  // not the published: the ordering-error diagnostic's (vicp_published_entry_distance)

void main()
{
    gl_Position = clip_position(vicp_mvp, vicp_published_position);
    VicpPublishedVaryings v = vicp_published_vertex_program(vicp_published_position, vicp_published_scalar_in, vicp_published_gradient,
                                                  vicp_published_plane, vicp_published_index);
    vicp_published_distance = v.distance;
    vicp_published_scalar = v.scalar;
    vicp_published_s = v.s;
    vicp_published_entry = vicp_published_position;
}
