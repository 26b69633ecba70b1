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

#include "core/model/configuration.h"
#include "core/model_io/model_loader.h"
#include "tools/eventlog/event_log.h"
#include "tools/ode_ref/ode_replay.h"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: igms-ode-ref log LOG [--track] [--out OUT.lcmlog] [--quickstep] [--base-dir DIR] [--json]\n"
               "       igms-ode-ref torques MODEL TORQUES.csv --out OUT.lcmlog [--dt H] [--q0 a,b,..] [--v0 a,b,..]\n"
               "                    [--floating-base] [--gravity x,y,z] [--damping] [--quickstep]\n");
  return 2;
}

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

int replayLog(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string path = argv[2];
  std::string out_path, base_dir = ".";
  bool json = false, track = false;
  igms::OdeSettings settings;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) out_path = argv[++i];
    else if (a == "--base-dir" && i + 1 < argc) base_dir = argv[++i];
    else if (a == "--quickstep") settings.quickstep = true;
    else if (a == "--json") json = true;
    else if (a == "--track") track = true;
    else return usage();
  }
  const igms::log::LogContents c = igms::log::readAll(path);
  if (c.damaged)
    std::fprintf(stderr, "igms-ode-ref: %s\nigms-ode-ref: using the %zu events before the damage\n", c.error.c_str(),
                 c.events.size());
  const igms::OdeReplayResult r = igms::replayOnOde(c.events, settings, base_dir, track);
  if (!r.ok && r.states.size() <= 1) {
    std::fprintf(stderr, "igms-ode-ref: %s: %s\n", path.c_str(), r.error.c_str());
    return 1;
  }
  if (!out_path.empty()) igms::writeStateLog(out_path, &r.info, r.states);
  const double seconds = r.steps * r.dt;
  if (json) {
    std::printf("{\"log\": \"%s\", \"ok\": %s, \"steps\": %lld, \"dt\": %.17g, \"q_max\": %.6g, \"q_rms\": %.6g, "
                "\"link_max\": %.6g, \"tracking\": %s, \"correction_rms\": %.6g, \"tau_rms\": %.6g, "
                "\"wall_s_per_s\": %.6g, \"link_max_by_second\": [",
                path.c_str(), r.ok ? "true" : "false", static_cast<long long>(r.steps), r.dt, r.q_max, r.q_rms,
                r.link_max, track ? "true" : "false", r.correction_rms, r.tau_rms,
                r.wall_seconds / std::max(seconds, 1e-9));
    for (size_t k = 0; k < r.link_max_by_second.size(); ++k)
      std::printf("%s%.6g", k ? ", " : "", r.link_max_by_second[k]);
    std::printf("]}\n");
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

int runTorques(int argc, char** argv) {
  if (argc < 4) return usage();
  const std::string model_path = argv[2], csv = argv[3];
  std::string out_path;
  double dt = 0.0;
  std::vector<double> q0, v0, gravity;
  igms::BuildOptions build;
  igms::OdeSettings settings;
  for (int i = 4; i < argc; ++i) {
    const std::string a = argv[i];
    const bool more = i + 1 < argc;
    if (a == "--out" && more) out_path = argv[++i];
    else if (a == "--dt" && more) dt = std::atof(argv[++i]);
    else if (a == "--q0" && more) { if (!parseList(argv[++i], q0)) return usage(); }
    else if (a == "--v0" && more) { if (!parseList(argv[++i], v0)) return usage(); }
    else if (a == "--gravity" && more) {
      if (!parseList(argv[++i], gravity) || gravity.size() != 3) return usage();
      build.gravity = igms::Vector3(gravity[0], gravity[1], gravity[2]);
    } else if (a == "--floating-base") build.floating_base = true;
    else if (a == "--damping") settings.joint_damping = true;
    else if (a == "--quickstep") settings.quickstep = true;
    else return usage();
  }
  if (out_path.empty()) return usage();
  try {
    const igms::Model m = igms::buildModel(igms::loadDescription(model_path), build);
    igms::VectorX q = igms::neutralConfiguration(m), v = igms::VectorX::Zero(m.nv);
    if (!q0.empty()) {
      if (static_cast<int>(q0.size()) != m.nq) {
        std::fprintf(stderr, "igms-ode-ref: --q0 has %zu values, %s has nq = %d\n", q0.size(), model_path.c_str(), m.nq);
        return 2;
      }
      q = Eigen::Map<igms::VectorX>(q0.data(), m.nq);
      igms::normalizeConfiguration(m, q);
    }
    if (!v0.empty()) {
      if (static_cast<int>(v0.size()) != m.nv) {
        std::fprintf(stderr, "igms-ode-ref: --v0 has %zu values, %s has nv = %d\n", v0.size(), model_path.c_str(), m.nv);
        return 2;
      }
      v = Eigen::Map<igms::VectorX>(v0.data(), m.nv);
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

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string cmd = argv[1];
  if (cmd == "log") return replayLog(argc, argv);
  if (cmd == "torques") return runTorques(argc, argv);
  return usage();
}
