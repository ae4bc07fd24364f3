// SPDX-License-Identifier: BSD-3-Clause
// nbs_eval: the thesis comparison (Sec. 4.7.2, Tab. 4.5, Figs. 4.19-4.21) on any mesh. See benchmarks/eval/config.hpp
// for the options and benchmarks/eval/main.hpp for the outputs; `nbs_eval --help` prints both.
#include "eval/main.hpp"

int main(int argc, char** argv) { return nbs::eval::main(argc, argv); }
