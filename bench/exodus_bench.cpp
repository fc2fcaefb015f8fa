// What reading an Exodus II file costs (docs/formats.md, "Exodus II"): `exodus_bench write N FILE` writes an N x N x N
// block of unit hexahedra (one nodal and one element variable, one time step) through libexodusii; `exodus_bench read
// FILE` loads it as `uvr` does (reference/dataset.h) and prints the load's seconds and the process's peak resident
// memory as JSON. bench/exodus_read.sh runs both.
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include <exodusII.h>

#include "reference/dataset.h"
#include "reference/error.h"

namespace {

int fail(const char* what)
{
    std::fprintf(stderr, "exodus_bench: %s failed\n", what);
    return 1;
}

int write_block(int n, const std::string& path)
{
    int cpu_ws = sizeof(double), io_ws = sizeof(double);
    const int exo = ex_create(path.c_str(), EX_CLOBBER | EX_LARGE_MODEL, &cpu_ws, &io_ws);
    if (exo < 0) return fail("ex_create");
    const int64_t m = n + 1, nodes = m * m * m, elems = int64_t(n) * n * n;
    if (ex_put_init(exo, "uvr exodus_bench", 3, nodes, elems, 1, 0, 0) < 0) return fail("ex_put_init");
    std::vector<double> x(nodes), y(nodes), z(nodes), temp(nodes), rho(elems);
    for (int64_t i = 0; i < nodes; ++i) {
        x[i] = double(i % m), y[i] = double(i / m % m), z[i] = double(i / (m * m));
        temp[i] = x[i] + 2.0 * y[i] - z[i];
    }
    if (ex_put_coord(exo, x.data(), y.data(), z.data()) < 0) return fail("ex_put_coord");
    if (ex_put_block(exo, EX_ELEM_BLOCK, 1, "HEX8", elems, 8, 0, 0, 0) < 0) return fail("ex_put_block");
    std::vector<int> conn;
    conn.reserve(std::size_t(8 * elems));
    const int64_t corner[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (int64_t k = 0; k < n; ++k)
        for (int64_t j = 0; j < n; ++j)
            for (int64_t i = 0; i < n; ++i) {
                for (const auto& c : corner) conn.push_back(int(1 + (i + c[0]) + m * ((j + c[1]) + m * (k + c[2]))));
                rho[std::size_t(i + n * (j + n * k))] = double((i + j + k) % 7);
            }
    if (ex_put_conn(exo, EX_ELEM_BLOCK, 1, conn.data(), nullptr, nullptr) < 0) return fail("ex_put_conn");
    char temp_name[] = "temperature", rho_name[] = "density";
    char* nodal[] = {temp_name};
    char* element[] = {rho_name};
    const double time = 0.0;
    if (ex_put_variable_param(exo, EX_NODAL, 1) < 0 || ex_put_variable_names(exo, EX_NODAL, 1, nodal) < 0 ||
        ex_put_variable_param(exo, EX_ELEM_BLOCK, 1) < 0 || ex_put_variable_names(exo, EX_ELEM_BLOCK, 1, element) < 0 ||
        ex_put_time(exo, 1, &time) < 0 || ex_put_var(exo, 1, EX_NODAL, 1, 1, nodes, temp.data()) < 0 ||
        ex_put_var(exo, 1, EX_ELEM_BLOCK, 1, 1, elems, rho.data()) < 0)
        return fail("writing the variables");
    return ex_close(exo) < 0 ? fail("ex_close") : 0;
}

int read_file(const std::string& path)
{
    const auto t0 = std::chrono::steady_clock::now();
    const uvr::Dataset d = uvr::load_dataset(path);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    std::printf("{\"seconds\": %.3f, \"peak_resident_bytes\": %lld, \"points\": %zu, \"tetrahedra\": %zu, "
                "\"fields\": %zu}\n",
                seconds, static_cast<long long>(ru.ru_maxrss) * 1024, d.mesh->points.size(), d.mesh->tets.size(),
                d.mesh->fields.size());
    return 0;
}

}  // namespace

int main(int argc, char** argv)
{
    const std::string mode = argc > 1 ? argv[1] : "";
    try {
        if (mode == "write" && argc == 4) return write_block(std::stoi(argv[2]), argv[3]);
        if (mode == "read" && argc == 3) return read_file(argv[2]);
    } catch (const uvr::InputError& e) {
        std::fprintf(stderr, "exodus_bench: %s\n", e.what());
        return 1;
    }
    std::fprintf(stderr, "usage: exodus_bench write N FILE | exodus_bench read FILE\n");
    return 2;
}
