// For the tests that hold two ways of compositing a pixel's fragments to the same bits (tests/test_havs_flush.cpp,
// tests/test_havs_pixel_sort.cpp): a segment colour that depends on every argument, so that a segment composited from
// the wrong pair, or in the wrong order, changes the framebuffer's bits; and the colours' bit comparison.
#pragma once

#include <cmath>
#include <cstring>

#include <glm/vec4.hpp>

namespace uvr::test {

inline glm::vec4 shade_of(float uf, float ub, float tz, float length)
{
    const float h = std::fabs(std::sin(uf * 12.9898f + ub * 78.233f + tz * 37.719f + length * 3.1f));
    return glm::vec4(0.3f * h, 0.2f * (1.0f - h), 0.1f * uf, 0.05f + 0.2f * h);
}

inline bool same_bits(const glm::vec4& a, const glm::vec4& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace uvr::test
