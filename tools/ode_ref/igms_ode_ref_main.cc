// igms-ode-ref: the same robot in ODE 0.16, driven by what igms applied.
//
//   igms-ode-ref log LOG [--track] [--out OUT.lcmlog] [--quickstep] [--base-dir DIR] [--json]
//       replays a recorded igms session in ODE (tools/ode_ref/ode_replay.h),
//       open loop or with --track the scene's PD gains on the deviation, and
//       prints how far ODE's trajectory is from igms's.
//   igms-ode-ref torques MODEL TORQUES.csv --out OUT.lcmlog [--dt H] [--q0 a,b,..] [--v0 a,b,..]
//                [--floating-base] [--gravity x,y,z] [--damping] [--quickstep]
//       applies a torque sequence: one CSV row per step, "t, tau_1 .. tau_nv"
//       (lines starting with '#' or a letter are skipped); h is --dt or the
//       spacing of t.
// The output is an igms state log (robot_state_t on IGMS_ROBOT_STATE), so
// igms-replay export and the plotting scripts read it as they read igms's own.
// Exit codes: 0 done, 1 the run failed (divergence, a log that cannot be
// replayed), 2 bad usage or input.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/cli/command_line.h"
#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "tools/eventlog/event_log.h"
#include "tools/ode_ref/ode_replay.h"

namespace {

bool parseList(const std::string& text, std::vector<double>& out) {
  out.clear();
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !std::isfinite(x)) return false;
    out.push_back(x);
  }
  return !out.empty();
}

struct LogOptions {
  std::string path, out_path, base_dir = ".";
  bool json = false, track = false;
  igms::OdeSettings settings;
};

void printJson(const LogOptions& o, const igms::OdeReplayResult& r) {
  const double seconds = r.steps * r.dt;
  const nlohmann::json j = {{"log", o.path},
                            {"ok", r.ok},
                            {"steps", r.steps},
                            {"dt", r.dt},
                            {"q_max", r.q_max},
                            {"q_rms", r.q_rms},
                            {"link_max", r.link_max},
                            {"tracking", o.track},
                            {"correction_rms", r.correction_rms},
                            {"tau_rms", r.tau_rms},
                            {"wall_s_per_s", r.wall_seconds / std::max(seconds, 1e-9)},
                            {"link_max_by_second", r.link_max_by_second}};
  std::printf("%s\n", j.dump().c_str());
}

int replayLog(const LogOptions& o) {
  const std::string& path = o.path;
  const std::string& out_path = o.out_path;
  const bool json = o.json, track = o.track;
  const igms::OdeSettings& settings = o.settings;
  const igms::log::LogContents c = igms::log::readAll(path);
  if (c.damaged)
    std::fprintf(stderr, "igms-ode-ref: %s\nigms-ode-ref: using the %zu events before the damage\n", c.error.c_str(),
                 c.events.size());
  const igms::OdeReplayResult r = igms::replayOnOde(c.events, settings, o.base_dir, track);
  if (!r.ok && r.states.size() <= 1) {
    std::fprintf(stderr, "igms-ode-ref: %s: %s\n", path.c_str(), r.error.c_str());
    return 1;
  }
  if (!out_path.empty()) igms::writeStateLog(out_path, &r.info, r.states);
  const double seconds = r.steps * r.dt;
  if (json) {
    printJson(o, r);
  } else {
    std::printf("%s: %lld steps of %.3g ms (%.2f s) on ODE %s, %s\n", path.c_str(), static_cast<long long>(r.steps),
                r.dt * 1e3, seconds, settings.quickstep ? "QuickStep" : "dWorldStep",
                track ? "tracking the recorded run with the scene's PD gains" : "open loop");
    std::printf("  ODE against the recorded igms run: joints max %.3g rad, rms %.3g rad; link origins max %.3g m\n",
                r.q_max, r.q_rms, r.link_max);
    std::printf("  link origins max per simulated second:");
    for (double x : r.link_max_by_second) std::printf(" %.2g", x);
    std::printf(" m\n");
    if (track)
      std::printf("  tracking torque rms %.3g N m against the recorded torques' rms %.3g N m\n", r.correction_rms,
                  r.tau_rms);
    std::printf("  ODE wall time: %.3g s per simulated second\n", r.wall_seconds / std::max(seconds, 1e-9));
    if (!out_path.empty()) std::printf("  wrote %s\n", out_path.c_str());
  }
  if (!r.ok) {
    std::fprintf(stderr, "igms-ode-ref: %s: %s\n", path.c_str(), r.error.c_str());
    return 1;
  }
  return 0;
}

struct TorqueOptions {
  std::string model_path, csv, out_path;
  double dt = 0.0;
  std::vector<double> q0, v0, gravity;
  igms::BuildOptions build;
  igms::OdeSettings settings;
};

int runTorques(TorqueOptions& o) {
  const std::string& model_path = o.model_path;
  const std::string& csv = o.csv;
  const std::string& out_path = o.out_path;
  double dt = o.dt;
  const std::vector<double>& q0 = o.q0;
  const std::vector<double>& v0 = o.v0;
  if (o.gravity.size() == 3) o.build.gravity = igms::Vector3(o.gravity[0], o.gravity[1], o.gravity[2]);
  const igms::BuildOptions& build = o.build;
  const igms::OdeSettings& settings = o.settings;
  try {
    const igms::Model m = igms::buildModel(igms::loadDescription(model_path), build);
    igms::VectorX q = igms::neutralConfiguration(m), v = igms::VectorX::Zero(m.nv);
    if (!q0.empty()) {
      if (static_cast<int>(q0.size()) != m.nq) {
        std::fprintf(stderr, "igms-ode-ref: --q0 has %zu values, %s has nq = %d\n", q0.size(), model_path.c_str(), m.nq);
        return 2;
      }
      q = Eigen::Map<const igms::VectorX>(q0.data(), m.nq);
      igms::normalizeConfiguration(m, q);
    }
    if (!v0.empty()) {
      if (static_cast<int>(v0.size()) != m.nv) {
        std::fprintf(stderr, "igms-ode-ref: --v0 has %zu values, %s has nv = %d\n", v0.size(), model_path.c_str(), m.nv);
        return 2;
      }
      v = Eigen::Map<const igms::VectorX>(v0.data(), m.nv);
    }
    std::ifstream in(csv);
    if (!in) {
      std::fprintf(stderr, "igms-ode-ref: %s: cannot open the file\n", csv.c_str());
      return 2;
    }
    std::vector<igms::VectorX> torques;
    std::vector<double> times, row;
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
      const size_t first = line.find_first_not_of(" \t\r");
      if (first == std::string::npos || line[first] == '#' || std::isalpha(static_cast<unsigned char>(line[first])))
        continue;
      std::string cleaned = line.substr(first);
      while (!cleaned.empty() && (cleaned.back() == '\r' || cleaned.back() == ' ')) cleaned.pop_back();
      if (!parseList(cleaned, row) || static_cast<int>(row.size()) != m.nv + 1) {
        std::fprintf(stderr, "igms-ode-ref: %s:%d: expected %d finite numbers (t and %d torques)\n", csv.c_str(),
                     line_no, m.nv + 1, m.nv);
        return 2;
      }
      times.push_back(row[0]);
      torques.push_back(Eigen::Map<igms::VectorX>(row.data() + 1, m.nv));
    }
    if (torques.empty()) {
      std::fprintf(stderr, "igms-ode-ref: %s: no torque rows\n", csv.c_str());
      return 2;
    }
    if (dt <= 0.0 && times.size() >= 2) dt = times[1] - times[0];
    if (!(dt > 0.0)) {
      std::fprintf(stderr, "igms-ode-ref: give --dt (one row cannot tell the step)\n");
      return 2;
    }
    const auto states = igms::runTorquesOnOde(m, q, v, torques, dt, settings);
    igms::writeStateLog(out_path, nullptr, states);
    const auto& last = states.back();
    bool finite = true;
    for (double x : last.q) finite = finite && std::isfinite(x);
    std::printf("%s: %zu steps of %.3g ms on ODE %s; wrote %s\n", model_path.c_str(), torques.size(), dt * 1e3,
                settings.quickstep ? "QuickStep" : "dWorldStep", out_path.c_str());
    if (!finite) {
      std::fprintf(stderr, "igms-ode-ref: ODE diverged\n");
      return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-ode-ref: %s\n", e.what());
    return 2;
  }
  return 0;
}

// "a,b,c" of finite numbers into a vector option.
CLI::Validator numberList(size_t count) {
  return CLI::Validator(
      [count](std::string& text) -> std::string {
        std::vector<double> v;
        if (!parseList(text, v)) return "expected finite numbers separated by commas, got '" + text + "'";
        if (count && v.size() != count) return "expected " + std::to_string(count) + " numbers";
        return "";
      },
      "a,b,..");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"", "igms-ode-ref"};
  igms::cli::describe(app, "The same robot in ODE 0.16, driven by what igms applied; writes an igms state log.");
  app.require_subcommand(1);
  LogOptions lo;
  auto* log_cmd = app.add_subcommand("log", "replay a recorded igms session in ODE and compare");
  log_cmd->add_option("LOG", lo.path, "the session log")->required()->check(CLI::ExistingFile);
  log_cmd->add_flag("--track", lo.track, "add the scene's PD gains on ODE's deviation from the recording");
  log_cmd->add_option("--out", lo.out_path, "write ODE's run as an igms state log");
  log_cmd->add_flag("--quickstep", lo.settings.quickstep, "ODE's iterative QuickStep instead of dWorldStep");
  log_cmd->add_option("--base-dir", lo.base_dir, "resolve the scene's relative paths from here");
  log_cmd->add_flag("--json", lo.json, "one JSON object on stdout");
  TorqueOptions to;
  std::string q0, v0, gravity;
  auto* torque_cmd = app.add_subcommand("torques", "apply a torque sequence (CSV rows: t, tau_1 .. tau_nv)");
  torque_cmd->add_option("MODEL", to.model_path, "URDF or DH table")->required()->check(CLI::ExistingFile);
  torque_cmd->add_option("TORQUES", to.csv, "CSV file")->required()->check(CLI::ExistingFile);
  torque_cmd->add_option("--out", to.out_path, "the state log to write")->required();
  torque_cmd->add_option("--dt", to.dt, "step, s (default: the spacing of t)")->check(igms::cli::positive("SECONDS"));
  torque_cmd->add_option("--q0", q0, "initial q")->check(numberList(0));
  torque_cmd->add_option("--v0", v0, "initial v")->check(numberList(0));
  torque_cmd->add_option("--gravity", gravity, "x,y,z")->check(numberList(3));
  torque_cmd->add_flag("--floating-base", to.build.floating_base, "a free root");
  torque_cmd->add_flag("--damping", to.settings.joint_damping, "apply the URDF's joint damping");
  torque_cmd->add_flag("--quickstep", to.settings.quickstep, "ODE's iterative QuickStep instead of dWorldStep");
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  if (*log_cmd) return replayLog(lo);
  if (!q0.empty()) parseList(q0, to.q0);
  if (!v0.empty()) parseList(v0, to.v0);
  if (!gravity.empty()) parseList(gravity, to.gravity);
  return runTorques(to);
}
