// The interpolation stage's harness (gpu/gl/gl_interpolation_harness.cpp): each vertex's clip coordinates and four
// attribute values from a storage buffer, handed to the rasterizer unchanged under the three qualifiers.
layout(std430, binding = 0) readonly buffer InterpolationVertices { vec4 interpolation_vertex[]; };

smooth out vec4 v_smooth;
noperspective out vec4 v_noperspective;
flat out vec4 v_flat;

void main()
{
    vec4 value = interpolation_vertex[2 * gl_VertexID + 1];
    gl_Position = interpolation_vertex[2 * gl_VertexID];
    v_smooth = value;
    v_noperspective = value;
    v_flat = value;
}
