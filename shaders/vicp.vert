// VICP's draw (gpu/vicp/gl_vicp.cpp): the vertex program's main. clip_position.vert, vicp_tet.glsl and vicp_vertex.vert
// are compiled in front of this file; vicp.frag is its fragment side.
//
// Two kinds of vertices, drawn in the stream's order by one glMultiDrawArrays(GL_TRIANGLES, ...) per chunk of the
// stream (gpu/vicp/gl_vicp.cpp): runs of whole cells and the fans of the cells the view cuts (gpu/vicp/vicp_clip.h), between
// them in their cells' places (GL keeps primitive order within a multi-draw as across draws).
//   - gl_VertexID < vicp_whole_vertices (12 times the chunk's cells): corner (gl_VertexID % 12) of cell
//     gl_VertexID / 12 of the chunk, corner 3f + j being vertex kVicpCorner[f][j] of face f (gpu/vicp/vicp_vertex.h), so
//     the four faces leave in the emulation's order; no vertex attributes.
//   - from vicp_whole_vertices on: corner j of the chunk's fan triangle k, (gl_VertexID - vicp_whole_vertices) =
//     3k + j, whose record (VicpFrameSetup::fans) holds its three vertices and its cell's slot in the whole stream.
//
// The constants are flat: the fragments see the provoking vertex's, which is each triangle's last (GL's default
// GL_LAST_VERTEX_CONVENTION; gpu/vicp/gl_vicp.cpp sets it). Only that vertex computes them, 4 of a whole cell's 12 (the
// emulation computes them once a cell: the same operations on the same inputs give the same bits); the others pass
// zeros, which no fragment reads. llvmpipe shades vertices on one thread, in double: at 10 million cells this is
// most of the frame (docs/vicp.md).

// ProjectTet's stream (VicpCell: four point indices, positively oriented, and the boundary mask), sent per frame.
layout(std430, binding = 0) readonly buffer VicpStream { uint vicp_stream[]; };
// Per frame: the vertex buffer (float positions relative to the eye: gl_Position, as HAVS), the snapped points (the
// drawn shape, relative to the mesh's centre). Resident: the points in double (the field's cell), normalized scalars.
// Three values a point, packed.
layout(std430, binding = 1) readonly buffer VicpPointsF { float vicp_points_f[]; };
layout(std430, binding = 2) readonly buffer VicpPointsD { double vicp_points_d[]; };
layout(std430, binding = 3) readonly buffer VicpScalars { double vicp_scalars[]; };
layout(std430, binding = 4) readonly buffer VicpSnapped { double vicp_snapped[]; };
// The chunk's fan triangles: three vertices (indices into VicpPointsF) and the cell's slot, four values each.
layout(std430, binding = 5) readonly buffer VicpFans { uint vicp_fans[]; };

uniform mat4 vicp_mvp;
uniform int vicp_whole_vertices;  // 12 times the chunk's cells
uniform uint vicp_slot_base;      // the chunk's first slot in the whole stream

const int vicp_corner[12] = int[12](1, 2, 3, 0, 3, 2, 0, 1, 3, 0, 2, 1);  // kVicpCorner, face by face

flat out VicpTet vicp_tet;

dvec3 vicp_point(uint i, bool snapped)
{
    return snapped ? dvec3(vicp_snapped[3u * i], vicp_snapped[3u * i + 1u], vicp_snapped[3u * i + 2u])
                   : dvec3(vicp_points_d[3u * i], vicp_points_d[3u * i + 1u], vicp_points_d[3u * i + 2u]);
}

void main()
{
    uint slot, p;
    int corner;  // 2: the provoking vertex
    if (gl_VertexID < vicp_whole_vertices) {
        slot = uint(gl_VertexID / 12);
        p = vicp_stream[5u * slot + uint(vicp_corner[gl_VertexID % 12])];
        corner = gl_VertexID % 3;
    } else {
        uint k = uint(gl_VertexID - vicp_whole_vertices);
        p = vicp_fans[4u * (k / 3u) + k % 3u];
        slot = vicp_fans[4u * (k / 3u) + 3u] - vicp_slot_base;
        corner = int(k % 3u);
    }
    gl_Position = clip_position(vicp_mvp, vec3(vicp_points_f[3u * p], vicp_points_f[3u * p + 1u],
                                               vicp_points_f[3u * p + 2u]));
    if (corner != 2) {
        vicp_tet = VicpTet(dvec3(0.0lf), dvec3[3](dvec3(0.0lf), dvec3(0.0lf), dvec3(0.0lf)), 0.0lf, dvec3(0.0lf),
                           dvec3[3](dvec3(0.0lf), dvec3(0.0lf), dvec3(0.0lf)), dvec3(0.0lf), 0.0lf, 0u);
        return;
    }
    uint v[4] = uint[4](vicp_stream[5u * slot], vicp_stream[5u * slot + 1u], vicp_stream[5u * slot + 2u],
                        vicp_stream[5u * slot + 3u]);
    uint boundary = vicp_stream[5u * slot + 4u];
    dvec3 shape[4], exact[4];
    double s[4];
    for (int i = 0; i < 4; ++i) {
        shape[i] = vicp_point(v[i], true);
        exact[i] = vicp_point(v[i], false);
        s[i] = vicp_scalars[v[i]];
    }
    vicp_tet = vicp_tet_constants(shape, exact, s, boundary);
}
