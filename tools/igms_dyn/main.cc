// igms-dyn: the command-line door to igms's kinematics and dynamics.
//   igms-dyn info  --model ROBOT.urdf [--floating-base]
//   igms-dyn info  --scene SCENE.yaml         the scene's environment: its robots and free bodies as parts
//   igms-dyn eval  --model ROBOT.urdf [--floating-base] < in.jsonl > out.jsonl
//   igms-dyn bench --model ROBOT.urdf [--floating-base] [--json]
// See docs/server.md (igms-dyn) for the JSON contract. Exit codes: 0 done, 1 a bad input
// line (eval), 2 a bad command line or model.
#include <iostream>
#include <string>

#include "core/cli/command_line.h"
#include "core/model_io/model_loader.h"
#include "core/scene/resolved_scene.h"
#include "tools/igms_dyn/commands.h"

int main(int argc, char** argv) {
  std::string model_path, scene_path;
  bool floating = false, json = false, verbose = false;
  CLI::App app{"", "igms-dyn"};
  igms::cli::describe(app, "igms's kinematics and dynamics on a URDF or DH model, as JSON.");
  app.require_subcommand(1);
  auto* info = app.add_subcommand("info", "nq, nv, joints and links as one JSON object");
  auto* eval = app.add_subcommand(
      "eval", "JSON lines {q, v, a?, tau?, fext?} on stdin -> {tau?, M, bias, qdd?, poses} on stdout");
  auto* bench = app.add_subcommand("bench", "median microseconds per call of rnea, crba, bias, fd, aba, fk, jacobian");
  // Before or after the subcommand: igms-dyn --verbose info ... and igms-dyn info ... --verbose.
  app.add_flag("--floating-base", floating, "a free root (7 q, 6 v first)");
  app.add_flag("--verbose", verbose, "print the model's load warnings");
  for (CLI::App* cmd : {info, eval, bench}) {
    auto* m = cmd->add_option("--model", model_path, "ROBOT.urdf or ROBOT.dh.yaml")->check(CLI::ExistingFile);
    auto* s = cmd->add_option("--scene", scene_path, "SCENE.yaml: its environment (robots and free bodies)")
                  ->check(CLI::ExistingFile);
    m->excludes(s);
    cmd->require_option(1, 2);
    cmd->fallthrough();
  }
  bench->add_flag("--json", json, "one JSON object");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;

  igms::Model model;
  std::vector<std::string> warnings;
  try {
    if (!scene_path.empty()) {
      const igms::ResolvedScene r = igms::resolveScene(igms::loadScene(scene_path));
      model = *r.model;
      warnings = r.warnings;
    } else {
      igms::BuildOptions options;
      options.floating_base = floating;
      model = igms::loadModel(model_path, options, &warnings);
    }
  } catch (const std::exception& e) {
    std::cerr << "igms-dyn: " << e.what() << "\n";
    return 2;
  }
  if (verbose)
    for (const auto& w : warnings) std::cerr << w << "\n";

  std::ios::sync_with_stdio(false);
  if (*info) return igms::dyn::info(model, std::cout);
  if (*eval) return igms::dyn::eval(model, std::cin, std::cout, std::cerr);
  return igms::dyn::bench(model, json, std::cout);
}
