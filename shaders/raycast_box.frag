// The published first two passes (gpu/raycast/raycast_box.h raycast_box_pass): the interpolated texture coordinate as
// the colour, alpha 1 marking a written texel (the target is cleared to 0).
smooth in vec3 rc_box_varying;
layout(location = 0) out vec4 rc_box_position_out;

void main()
{
    rc_box_position_out = vec4(rc_box_varying, 1.0);
}
