// HAVS's CPU stage: the radix sort of faces by squared centroid distance.
#include <algorithm>
#include <numeric>
#include <cmath>
#include <random>

#include "gpu/pipeline/face_sort.h"
#include "test_support.h"

using namespace uvr::gpu;

namespace {

std::vector<uint32_t> stable_sorted(const std::vector<float>& keys)
{
    std::vector<uint32_t> idx(keys.size());
    std::iota(idx.begin(), idx.end(), 0u);
    std::stable_sort(idx.begin(), idx.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
    return idx;
}

}  // namespace

TEST_CASE("the radix sort equals std::stable_sort on the same keys")
{
    std::mt19937 rng(4);
    std::vector<uint32_t> order, scratch;
    SECTION("random distances over many orders of magnitude")
    {
        std::vector<float> keys(100000);
        std::uniform_real_distribution<float> e(-20.0f, 20.0f);
        for (auto& k : keys) k = std::exp2(e(rng));
        radix_sort_faces(keys, order, scratch);
        CHECK(order == stable_sorted(keys));
    }
    SECTION("many exact ties keep their index order")
    {
        std::vector<float> keys(50000);
        std::uniform_int_distribution<int> small(0, 40);
        for (auto& k : keys) k = float(small(rng)) * 0.25f;
        radix_sort_faces(keys, order, scratch);
        CHECK(order == stable_sorted(keys));
    }
    SECTION("zero, negative zero, denormals and huge values")
    {
        const std::vector<float> keys{3.0f, 0.0f, -0.0f, 1e-40f, 3.0e38f, 1e-45f, 0.0f, 2.5f};
        radix_sort_faces(keys, order, scratch);
        std::vector<float> positive = keys;
        positive[2] = 0.0f;
        CHECK(order == stable_sorted(positive));
    }
    SECTION("an empty list")
    {
        radix_sort_faces({}, order, scratch);
        CHECK(order.empty());
    }
}

TEST_CASE("face keys are squared distances from the eye to the face centroids")
{
    const std::vector<glm::vec3> p{{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {0, 0, 9}};
    const std::vector<uint32_t> faces{0, 1, 2, 0, 1, 3};
    std::vector<float> keys;
    face_sort_keys(p, faces, glm::vec3(1, 1, 1), keys);
    REQUIRE(keys.size() == 2);
    CHECK(keys[0] == Approx(1.0f));  // centroid (1, 1, 0)
    CHECK(keys[1] == Approx(1.0f + 0.0f + 4.0f));  // centroid (1, 0, 3): (0)^2 + (-1)^2 + 2^2
    std::vector<uint32_t> order, scratch;
    radix_sort_faces(keys, order, scratch);
    CHECK(order == std::vector<uint32_t>{0, 1});
}
