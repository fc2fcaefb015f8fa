// HAVS's and VICP's programs compile on the image route with the ARB interlock (gpu/gl/gl_fragment_access.h), which
// no machine here runs (llvmpipe has none), compiled offline by Debian's glslangValidator beside llvmpipe's image
// route, which the GL tests also run; and the ray caster's programs. Debian 12's glslang (12.0) does not know GL_NV_fragment_shader_interlock, so the
// NV variant (the same text with NV's names) is not compiled here.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "gpu/gl/gl_context.h"
#include "gpu/gl/gl_fragment_access.h"
#include "gpu/havs/gl_havs.h"
#include "gpu/raycast/gl_raycast.h"
#include "gpu/vicp/gl_vicp.h"
#include "test_support.h"

using namespace uvr;
using namespace uvr::gpu;
using uvr::test::TempDir;

namespace {

// The routes: the ARB interlock a desktop GPU offers, and llvmpipe's image route without one.
const FragmentAccessPath kRoutes[] = {{true, "ARB", "GL_ARB_fragment_shader_interlock"}, {true, "", ""}};

// Compiles one stage with glslangValidator (OpenGL semantics, the stage by the file's extension); the log on failure.
std::string compile(const TempDir& tmp, const std::string& name, const GlShaderSource& src)
{
    const std::string path = tmp.write(name, assembled_source(src));
    const std::string log = tmp.file(name + ".log");
    const std::string command = "glslangValidator '" + path + "' > '" + log + "' 2>&1";
    if (std::system(command.c_str()) == 0) return "";
    return test::file_contents(log);
}

std::string route_name(const FragmentAccessPath& p)
{
    return p.interlock.empty() ? "llvmpipe's image route" : p.interlock + " interlock";
}

}  // namespace

TEST_CASE("HAVS's and VICP's programs compile on the image route with the ARB interlock and without, in glslang")
{
    REQUIRE(std::system("glslangValidator --version > /dev/null 2>&1") == 0);  // glslang-tools, install-deps.sh
    TempDir tmp("glsl-variants");
    int n = 0;
    for (const FragmentAccessPath& route : kRoutes) {
        for (const bool diagnostics : {false, true})
            for (const bool published : {false, true}) {
                const auto src = GlHavsRenderer::program_sources(6, diagnostics, published, published, route);
                for (const auto& [stage, s] : {std::pair{"geometry.frag", &src.geometry_fragment},
                                               std::pair{"geometry.vert", &src.geometry_vertex},
                                               std::pair{"flush.frag", &src.flush_fragment}}) {
                    const std::string name = "havs" + std::to_string(n++) + "-" + stage;
                    INFO("HAVS, " << route_name(route) << (diagnostics ? ", diagnostics" : "")
                                  << (published ? ", the paper's varyings and entries" : "") << ": " << stage);
                    CHECK(compile(tmp, name, *s) == "");
                }
            }
        const auto v = GlVicpRenderer::program_sources(route);
        for (const auto& [stage, s] :
             {std::pair{"exact.frag", &v.exact_fragment}, std::pair{"exact.vert", &v.exact_vertex},
              std::pair{"published.frag", &v.published_fragment}, std::pair{"published.vert", &v.published_vertex}}) {
            INFO("VICP, " << route_name(route) << ": " << stage);
            CHECK(compile(tmp, "vicp" + std::to_string(n++) + "-" + stage, *s) == "");
        }
    }
}

TEST_CASE("the ray caster's programs compile in glslang, published passes or not, lit or not")
{
    REQUIRE(std::system("glslangValidator --version > /dev/null 2>&1") == 0);
    TempDir tmp("glsl-raycast");
    int n = 0;
    for (const bool published : {false, true})
        for (const bool light : {false, true}) {
            const auto src = GlRaycastRenderer::program_sources(published, light);
            for (const auto& [stage, s] :
                 {std::pair{"march.frag", &src.march_fragment}, std::pair{"march.vert", &src.march_vertex},
                  std::pair{"box.frag", &src.box_fragment}, std::pair{"box.vert", &src.box_vertex}}) {
                INFO("ray caster" << (published ? ", the published passes" : "") << (light ? ", lit" : "") << ": "
                                  << stage);
                CHECK(compile(tmp, "raycast" + std::to_string(n++) + "-" + stage, *s) == "");
            }
        }
}

