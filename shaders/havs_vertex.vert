// HAVS's vertex stage (seed 000, Appendix I): the GLSL twin of gpu/pipeline/clip_position.cpp's clip_position, which
// clip_position.vert (compiled in front of this file) holds. The face's vertices come from the vertex buffer of float
// positions relative to the eye (HavsFrameSetup::points_f).

layout(location = 0) in vec3 havs_position;
uniform mat4 havs_mvp;  // column-major, as Mat4f

void main()
{
    gl_Position = clip_position(havs_mvp, havs_position);
}
