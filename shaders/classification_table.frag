// The ray caster's post-classification table (gpu/raycast/classification_table.h): N x 1 RGBA32F, GL_LINEAR, CLAMP_TO_EDGE,
// uploaded by upload_raycast_textures (gpu/raycast/gl_raycast.h), read at the normalized scalar x and t = 0.5. Its
// emulation is ClassificationTable::sample (gpu/pipeline/texture_sampling.cpp's sample_2d).
layout(binding = 1) uniform sampler2D classification_table;

vec4 classification_lookup(float x)
{
    return texture(classification_table, vec2(x, 0.5));
}
