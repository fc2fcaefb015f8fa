// `uvr`: the laboratory's one program (bench/program.h).
#include "bench/program.h"

int main(int argc, char** argv)
{
    return uvr::cli::run_program(argc, argv);
}
