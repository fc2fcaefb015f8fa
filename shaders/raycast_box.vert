// The box the published passes draw (gpu/raycast/raycast_box.h: the vertices raycast_box_frame made, three a triangle):
// the position through clip_position (clip_position.vert, compiled in front), the texture coordinate interpolated
// `smooth` (perspective-correct), as the published colour is. All three passes draw with it
// (gpu/raycast/gl_raycast.cpp).
layout(location = 0) in vec3 rc_box_position;  // relative to the eye
layout(location = 1) in vec3 rc_box_tex;

uniform mat4 rc_box_mvp;

smooth out vec3 rc_box_varying;

void main()
{
    gl_Position = clip_position(rc_box_mvp, rc_box_position);
    rc_box_varying = rc_box_tex;
}
