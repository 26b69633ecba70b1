// igms-server --scene scenes/puma_wall.yaml [--lcm-url URL] [--clock realtime|lockstep] ...

#include "bus/bus_key.h"
#include "core/cli/command_line.h"
#include "core/realtime/stop_signal.h"
#include "server/app/server.h"

int main(int argc, char** argv) {
  igms::ServerOptions o;
  CLI::App app{"", "igms-server"};
  igms::cli::describe(app,
                      "The dynamics server: runs a scene, takes haptic inputs and commands from LCM, publishes the "
                      "robot state every step. Run it inside scripts/netns_run.sh when the URL is udpm:// (the "
                      "default).");
  app.add_option("--scene", o.scene_path, "scene file (YAML)")->required()->check(CLI::ExistingFile);
  app.add_option("--lcm-url", o.lcm_url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")->check(igms::cli::LcmUrl);
  std::string clock = "realtime";
  app.add_option("--clock", clock, "realtime: steps on absolute deadlines; lockstep: one step per input")
      ->check(CLI::IsMember({"realtime", "lockstep"}));
  app.add_option("--duration", o.duration, "simulated seconds to run (0: until stopped)")->check(igms::cli::Seconds);
  app.add_option("--save-edited", o.save_edited, "write the edited trajectory here on exit");
  app.add_option("--session-token", o.session_token, "the session token (0: random)");
  app.add_flag("--paused", o.start_paused, "start paused (START or STEP commands go on)");
  app.add_option("--input-hold", o.input_hold, "s an input keeps acting without a newer one (realtime clock)")
      ->check(igms::cli::Seconds);
  app.add_flag("--quiet", o.quiet, "no status lines on stderr");
  app.add_option("--rt-priority", o.rt_priority,
                 "ask for SCHED_FIFO at this priority (1-99) for every thread (the loop, the bus, publishing) and "
                 "lock memory; a warning and a normal process when not allowed (0: do not ask)")
      ->check(CLI::Range(0, 99));
  app.add_option("--key-file", o.key_file, igms::bus::kKeyFileHelp)->envname(igms::bus::kKeyFileEnv);
  app.add_flag("--accept-replay", o.accept_replay, igms::bus::kAcceptReplayHelp);
  app.add_option("--scene-dir", o.commands.scene_dirs, "LOAD_SCENE only from these folders (default: --scene's folder)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--output-dir", o.commands.output_dir, "SAVE_TRAJECTORY only into this folder (default: .)")
      ->check(CLI::ExistingDirectory);
  app.add_option("--contact-rate", o.contact_rate,
                 "Hz at most of the contacts channel IGMS_CONTACTS, scenes with contact only (0: none)")
      ->check(igms::cli::nonNegative("HZ"));
  auto* faults = app.add_option_group("fault injection", "on the published states, to test a client's fallbacks");
  faults->add_option("--fault-drop", o.fault_drop, "fraction of states not published")->check(CLI::Range(0.0, 1.0));
  faults->add_option("--fault-burst-ms", o.fault_burst_ms, "every second, no states for this long")
      ->check(igms::cli::nonNegative("MS"));
  faults->add_option("--fault-delay-us", o.fault_delay_us, "every state published this much later")
      ->check(igms::cli::nonNegative("US"));
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  o.clock = clock == "lockstep" ? igms::ServerOptions::Clock::Lockstep : igms::ServerOptions::Clock::Realtime;
  if (o.commands.scene_dirs.empty()) {
    const size_t slash = o.scene_path.rfind('/');
    o.commands.scene_dirs.push_back(slash == std::string::npos ? "." : o.scene_path.substr(0, slash + 1));
  }
  return igms::runServer(o, igms::stopOnSignals());
}
