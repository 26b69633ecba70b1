// igms-dyn: the command-line door to igms's kinematics and dynamics.
//   igms-dyn info  --model ROBOT.urdf [--floating-base]
//   igms-dyn eval  --model ROBOT.urdf [--floating-base] < in.jsonl > out.jsonl
//   igms-dyn bench --model ROBOT.urdf [--floating-base] [--json]
// See README.md for the JSON contract.
#include <cstring>
#include <iostream>
#include <string>

#include "core/model_io/model_loader.h"
#include "tools/igms_dyn/commands.h"

namespace {

int usage(const char* why) {
  if (why) std::cerr << "igms-dyn: " << why << "\n";
  std::cerr << "usage: igms-dyn info|eval|bench --model ROBOT.urdf|ROBOT.dh.yaml [--floating-base] [--json]\n"
               "  info   print nq, nv, joints and links as one JSON object\n"
               "  eval   read JSON lines {q, v, a?, tau?, fext?} on stdin, write {tau?, M, bias, qdd?, poses}\n"
               "  bench  median microseconds per call of rnea, crba, bias, fd, aba, fk, jacobian\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage(nullptr);
  const std::string command = argv[1];
  if (command == "-h" || command == "--help") {
    usage(nullptr);
    return 0;
  }
  std::string model_path;
  bool floating = false, json = false, verbose = false;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--model" && i + 1 < argc) {
      model_path = argv[++i];
    } else if (arg == "--floating-base") {
      floating = true;
    } else if (arg == "--json") {
      json = true;
    } else if (arg == "--verbose") {
      verbose = true;
    } else {
      return usage(("unknown argument '" + arg + "'").c_str());
    }
  }
  if (command != "info" && command != "eval" && command != "bench")
    return usage(("unknown command '" + command + "'").c_str());
  if (model_path.empty()) return usage("--model is required");

  igms::Model model;
  std::vector<std::string> warnings;
  try {
    igms::BuildOptions options;
    options.floating_base = floating;
    model = igms::loadModel(model_path, options, &warnings);
  } catch (const std::exception& e) {
    std::cerr << "igms-dyn: " << e.what() << "\n";
    return 2;
  }
  if (verbose)
    for (const auto& w : warnings) std::cerr << w << "\n";

  std::ios::sync_with_stdio(false);
  if (command == "info") return igms::dyn::info(model, std::cout);
  if (command == "eval") return igms::dyn::eval(model, std::cin, std::cout, std::cerr);
  return igms::dyn::bench(model, json, std::cout);
}
