// igms-haptic --scene scenes/puma_obstacle.yaml --device scripted:scenes/push_demo.yaml [...]

#include "bus/bus_key.h"
#include "core/cli/command_line.h"
#include "core/realtime/stop_signal.h"
#include "haptic_client/app/haptic_client.h"
#include "haptic_client/device/device_registry.h"

int main(int argc, char** argv) {
  igms::ClientOptions o;
  CLI::App app{"", "igms-haptic"};
  igms::cli::describe(app,
                      "The haptic client: the 1 kHz servo loop between a device and igms-server. Run it inside "
                      "scripts/netns_run.sh when the URL is udpm:// (the default).");
  app.footer("Devices (--device NAME[:ARGS]):\n" + igms::DeviceRegistry::usage());
  app.add_option("--scene", o.scene_path, "the server's scene file (YAML)")->required()->check(CLI::ExistingFile);
  app.add_option("--device", o.device, "NAME[:ARGS], see below")->required();
  app.add_option("--lcm-url", o.lcm_url, "LCM URL (default udpm://239.255.76.67:7667?ttl=0)")->check(igms::cli::LcmUrl);
  app.add_option("--key-file", o.key_file, igms::bus::kKeyFileHelp)->envname(igms::bus::kKeyFileEnv);
  app.add_flag("--accept-replay", o.accept_replay, igms::bus::kAcceptReplayHelp);
  app.add_option("--rate", o.servo.rate_hz, "servo rate")->check(igms::cli::positive("HZ"));
  app.add_option("--deadline-us", o.servo.deadline_us,
                 "while replies come back within this long, wait this long for this cycle's")
      ->check(igms::cli::positive("US"));
  app.add_option("--fallback", o.fallback,
                 "how the robot is estimated from a state of some age: predict (its q, v, qdd carried to now), "
                 "hold, extrapolate (link poses), interpolate")
      ->check(CLI::IsMember({"predict", "hold", "extrapolate", "interpolate"}));
  app.add_option("--max-prediction-ms", o.max_prediction_ms, "predict at most this far ahead of a state")
      ->check(igms::cli::nonNegative("MS"));
  app.add_option("--local-budget-us", o.servo.local_budget_us,
                 "predict: the local model's compute per cycle (its steps are timed at start to fit it, and a run stops "
                 "stepping once it has taken it)")
      ->check(igms::cli::positive("US"));
  bool no_passivity = false;
  double passivity_tolerance_mj = o.servo.passivity_tolerance * 1e3;
  app.add_flag("--no-passivity", no_passivity,
               "turn the time-domain passivity controller off (its observer still reports the energy balance)");
  app.add_option("--passivity-tolerance-mj", passivity_tolerance_mj,
                 "how far the energy balance may dip (the robot handing back its own motion) before it acts")
      ->check(igms::cli::nonNegative("MJ"));
  app.add_option("--lost-ms", o.servo.lost_ms, "no new state for this long: the server is lost, forces ramp down")
      ->check(igms::cli::positive("MS"));
  app.add_option("--client-id", o.servo.client_id, "this client's id in its inputs");
  app.add_option("--duration", o.servo.duration, "seconds to run (0: until the device's script ends)")
      ->check(igms::cli::Seconds);
  app.add_option("--connect-timeout", o.connect_timeout, "seconds to wait for the server's first status")
      ->check(igms::cli::positive("SECONDS"));
  app.add_flag("--quiet", o.quiet, "no start and summary lines on stderr");
  app.add_option("--record", o.record,
                 "after the run, write every cycle's tip, proxy, the coupling's force and the rendered force here (CSV; "
                 "kept in memory during the run: the duration's or the script's cycles, else the first 10 minutes)");
  app.add_option("--export-targets", o.export_targets,
                 "after the run, write a scripted device's targets as its device saw them (device frame, link "
                 "waypoints resolved) for the example device plugin (examples/device_plugin)");
  app.add_option("--rt-priority", o.rt_priority,
                 "ask for SCHED_FIFO at this priority (1-99) for every thread (the servo loop, the bus, the "
                 "status) and lock memory; a warning and a normal process when not allowed (0: do not ask)")
      ->check(CLI::Range(0, 99));
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  o.servo.passivity = !no_passivity;
  o.servo.passivity_tolerance = passivity_tolerance_mj * 1e-3;
  return igms::runClient(o, igms::stopOnSignals());
}
