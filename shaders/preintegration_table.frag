// The 3D pre-integrated table (gpu/pipeline/preintegration_table.h) as the fragment programs of HAVS and VICP sample
// it: texture 4 of the HAVS paper's programs, GL_LINEAR (or GL_NEAREST, --filter), CLAMP_TO_EDGE, uploaded by
// upload_preintegration_table (gpu/gl/gl_preintegration_table.h). Its emulation, texel for texel and weight for weight
// as llvmpipe filters, is gpu/pipeline/texture_sampling.cpp.
layout(binding = 4) uniform sampler3D preintegration_table;

vec4 preintegration_lookup(float u_front, float u_back, float t_z)
{
    return texture(preintegration_table, vec3(u_front, u_back, t_z));
}
