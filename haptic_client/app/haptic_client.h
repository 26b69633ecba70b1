// igms-haptic: the haptic client. Composed of named parts:
//   DeviceRegistry (device/)      --device NAME[:ARGS] -> a HapticDevice
//   ClientBus (servo/)            states and the server's status in, inputs out
//   ClientStatusThread (servo/)   the bus thread: receives, sends the client status at 10 Hz
//   ServoLoop (servo/)            the 1 kHz loop: device, input, state or fallback, force
#pragma once

#include <atomic>
#include <string>

#include "haptic_client/servo/servo_loop.h"

namespace igms {

struct ClientOptions {
  std::string scene_path;
  std::string device;          // NAME[:ARGS], e.g. "scripted:FILE"
  std::string lcm_url;
  std::string fallback = "predict";
  double max_prediction_ms = 100.0;  // the predict policy's furthest step ahead of a state
  ServoConfig servo;           // the loop's rate, deadline, duration, id, local budget, passivity
  double connect_timeout = 10.0;  // s to wait for the server's first status
  bool quiet = false;
  int rt_priority = 0;         // > 0: the servo loop asks for SCHED_FIFO at this priority and locks memory
  std::string key_file;        // the bus key (bus/bus_key.h); "": the bus is unauthenticated
  bool accept_replay = false;  // take replayed traffic (igms-replay play) too
  std::string export_targets;  // a scripted device's targets, after the run, for the example plugin
  std::string record;          // every cycle's tip and forces, as CSV after the run (servo_record.h)
};

// Returns the exit code: 0 done, 2 setup error, 3 no server.
int runClient(const ClientOptions& options, const std::atomic<bool>& stop);

}  // namespace igms
