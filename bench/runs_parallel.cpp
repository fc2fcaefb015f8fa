#include "bench/runs_parallel.h"

#include <cstring>

#include <nlohmann/json.hpp>

#include "distributed/exchange.h"
#include "distributed/mpi_runtime.h"
#include "reference/error.h"

namespace uvr::cli {

namespace {

// A run's result as bytes: tag, ms, stats (JSON text), ordering errors, width, height, RGBA.
class RunWriter {
public:
    void put(const AlgoResult& r, const std::string& tag)
    {
        text(tag);
        pod(r.ms);
        text(r.stats.dump());
        pod(uint64_t(r.ordering_errors.size()));
        raw(r.ordering_errors.data(), r.ordering_errors.size() * sizeof(uint32_t));
        pod(int32_t(r.image.width));
        pod(int32_t(r.image.height));
        raw(r.image.rgba.data(), r.image.rgba.size() * sizeof(float));
    }
    const std::vector<char>& bytes() const { return bytes_; }

private:
    std::vector<char> bytes_;

    void raw(const void* p, std::size_t n)
    {
        bytes_.insert(bytes_.end(), static_cast<const char*>(p), static_cast<const char*>(p) + n);
    }
    template <class T>
    void pod(T v)
    {
        raw(&v, sizeof v);
    }
    void text(const std::string& s)
    {
        pod(uint64_t(s.size()));
        raw(s.data(), s.size());
    }
};

class RunReader {
public:
    explicit RunReader(const std::vector<char>& bytes) : bytes_(bytes) {}
    bool done() const { return at_ == bytes_.size(); }
    std::string take(AlgoResult& r)
    {
        const std::string tag = text();
        r.ms = pod<double>();
        r.stats = nlohmann::json::parse(text());
        r.ordering_errors.resize(std::size_t(pod<uint64_t>()));
        raw(r.ordering_errors.data(), r.ordering_errors.size() * sizeof(uint32_t));
        const int32_t width = pod<int32_t>(), height = pod<int32_t>();
        r.image = Image(width, height);
        raw(r.image.rgba.data(), r.image.rgba.size() * sizeof(float));
        return tag;
    }

private:
    const std::vector<char>& bytes_;
    std::size_t at_ = 0;

    void raw(void* p, std::size_t n)
    {
        if (n == 0) return;  // an empty vector's data() may be null, which memcpy must not be given
        if (n > bytes_.size() - at_) throw std::logic_error("a run's bytes end early");
        std::memcpy(p, bytes_.data() + at_, n);
        at_ += n;
    }
    template <class T>
    T pod()
    {
        T v{};
        raw(&v, sizeof v);
        return v;
    }
    std::string text()
    {
        std::string s(std::size_t(pod<uint64_t>()), '\0');
        raw(s.data(), s.size());
        return s;
    }
};

}  // namespace

std::map<std::string, AlgoResult> render_across_ranks(Scene& scene, const std::vector<PlannedRun>& runs,
                                                      std::vector<char> wanted)
{
    wanted.resize(runs.size());
    mpi::broadcast_bytes(wanted);
    std::vector<std::size_t> dealt;
    for (std::size_t i = 0; i < runs.size(); ++i)
        if (wanted[i]) dealt.push_back(i);
    // One run a rank a round, so that a message holds one image per rank.
    const std::size_t ranks = std::size_t(mpi::ranks());
    std::map<std::string, AlgoResult> out;
    const Camera camera = scene.camera;
    for (std::size_t first = 0; first < dealt.size(); first += ranks) {
        RunWriter mine;
        mpi::on_every_rank([&] {
            const std::size_t at = first + std::size_t(mpi::rank());
            if (at >= dealt.size()) return;
            const PlannedRun& run = runs[dealt[at]];
            scene.camera = run.camera;
            mine.put(run_algorithm(scene, run.algo, run.options), run.tag);
        });
        for (const std::vector<char>& bytes : mpi::gather_bytes(mine.bytes())) {
            RunReader reader(bytes);
            while (!reader.done()) {
                AlgoResult r;
                const std::string tag = reader.take(r);
                out.emplace(tag, std::move(r));
            }
        }
    }
    scene.camera = camera;
    return out;
}

}  // namespace uvr::cli
