// HAVS's vertex stage (the HAVS paper, Appendix I): the GLSL twin of gpu/pipeline/clip_position.cpp's clip_position
// (exact interpolation) or dp4_position (the paper's program), which clip_position.vert (compiled in front of this
// file) holds. The face's vertices come from the vertex buffer of float positions relative to the eye
// (HavsFrameSetup::points_f). With HAVS_PAPER_VARYINGS (--interpolation gpu) it is the paper's vertex program whole:
// the eye-space position by the same product with the model-view (texture coordinate 1 of the paper), the scalar
// (texture coordinate 0) and the face's side, a per-face attribute every vertex of the face carries (the vertices are
// not shared), for the rasterizer to interpolate; and the triangle's corners (noperspective), from which the fragment
// program tells a pixel outside its triangle (covered through snapping). The emulated twin is havs_paper_vertices and
// HavsFrameSetup::s_f (gpu/havs/havs_setup.cpp) and havs_varying_planes (gpu/havs/havs_fragment.cpp).

uniform mat4 havs_mvp;  // column-major, as Mat4f; the paper's program: state.matrix.mvp (ViewSetup::driver_mvp)

#ifndef HAVS_PAPER_VARYINGS
layout(location = 0) in vec3 havs_position;
#else
layout(location = 0) in vec4 havs_position;  // three components fed: w is the default 1, as vertex.position's
layout(location = 1) in float havs_scalar;
layout(location = 2) in float havs_side;
uniform mat4 havs_mv;  // the model-view for positions relative to the eye (ViewSetup::view)
smooth out vec3 havs_eye_position;
smooth out float havs_eye_scalar;
flat out float havs_face_side;
noperspective out vec3 havs_corner;  // (1, 0, 0), (0, 1, 0), (0, 0, 1) at the triangle's three vertices
#endif

void main()
{
#ifndef HAVS_PAPER_VARYINGS
    gl_Position = clip_position(havs_mvp, havs_position);
#else
    gl_Position = dp4_position(havs_mvp, havs_position);
    havs_eye_position = dp4_position(havs_mv, havs_position).xyz;
    havs_eye_scalar = havs_scalar;
    havs_face_side = havs_side;
    // A draw's vertices are its triangles' three in order (unshared), so the corner is the vertex's index mod 3.
    int corner = gl_VertexID % 3;
    havs_corner = vec3(corner == 0 ? 1.0 : 0.0, corner == 1 ? 1.0 : 0.0, corner == 2 ? 1.0 : 0.0);
#endif
}
