// VICP's seed draw (--interpolation gpu, gpu/vicp/gl_vicp.cpp): the vertex program's main. clip_position.vert,
// vicp_seed.glsl and vicp_seed_vertex.vert are compiled in front of this file; vicp_seed.frag is its fragment side.
// ProjectTet's records arrive as vertex attributes (VicpSeedVertex, 11 floats, twelve vertices a cell: face f's
// vertex j at 3 f + j), streamed in chunks; VertexProg's varyings leave `smooth`, as the seed's texture coordinates.
layout(location = 0) in vec3 vicp_seed_position;  // relative to the eye
layout(location = 1) in float vicp_seed_scalar_in;
layout(location = 2) in vec3 vicp_seed_gradient;
layout(location = 3) in vec3 vicp_seed_plane;
layout(location = 4) in float vicp_seed_index;

uniform mat4 vicp_mvp;

smooth out vec3 vicp_seed_distance;
smooth out vec3 vicp_seed_scalar;
smooth out float vicp_seed_s;
smooth out vec3 vicp_seed_entry;  // not the seed's: the ordering-error diagnostic's (vicp_seed_entry_distance)

void main()
{
    gl_Position = clip_position(vicp_mvp, vicp_seed_position);
    VicpSeedVaryings v = vicp_seed_vertex_program(vicp_seed_position, vicp_seed_scalar_in, vicp_seed_gradient,
                                                  vicp_seed_plane, vicp_seed_index);
    vicp_seed_distance = v.distance;
    vicp_seed_scalar = v.scalar;
    vicp_seed_s = v.s;
    vicp_seed_entry = vicp_seed_position;
}
