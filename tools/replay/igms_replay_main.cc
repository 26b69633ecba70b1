// igms-replay: play back, re-simulate and export igms session logs.
//
//   igms-replay info   LOG
//   igms-replay play   LOG [--speed X | --fast] [--channel REGEX] [--remap FROM=TO]... [--start S] [--end S]
//                          [--loop] [--step] [--lcm-url URL] [--key-file FILE] [--with-commands]
//     With a key, what it publishes is signed as a replay (message_signature.h): programs that act on the
//     bus (server, client, device) refuse it unless started with --accept-replay. Commands are left out
//     unless --with-commands, and a recorded message whose signature does not hold under the key is left out.
//   igms-replay resim  LOG [--tolerance T] [--require-identical] [--base-dir DIR] [--json]
//   igms-replay export LOG DIR            (CSV files and the scene, for plots; obstacles.csv: the distance to
//                                         each obstacle; environment.csv for an environment)
//
// A damaged log gives a clear error with the byte offset; the events before
// the damage are still used (exit code 3 then, unless the command failed).
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <lcm/lcm-cpp.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>
#include <thread>
#include <vector>

#include "bus/bus_key.h"
#include "bus/message_signature.h"
#include "bus/message_verifier.h"
#include "bus/signed_publisher.h"
#include "channels.h"
#include "core/cli/command_line.h"
#include "core/cli/round_trip.h"
#include "core/kinematics/forward_kinematics.h"
#include "core/model/environment_model.h"
#include "core/model_io/zlib_text.h"
#include "core/realtime/stop_signal.h"
#include "igms/client_status_t.hpp"
#include "igms/command_t.hpp"
#include "igms/haptic_input_t.hpp"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "igms/session_files_t.hpp"
#include "igms/session_info_t.hpp"
#include "server/collision/collision_world.h"
#include "tools/eventlog/event_log.h"
#include "tools/replay/resimulate.h"
#include "safe_decode.h"

namespace {


igms::log::LogContents load(const std::string& path) {
  igms::log::LogContents c = igms::log::readAll(path);
  if (c.damaged)
    std::fprintf(stderr, "igms-replay: %s\nigms-replay: using the %zu events before the damage\n", c.error.c_str(),
                 c.events.size());
  return c;
}

int info(const std::string& path) {
  const auto c = load(path);
  std::map<std::string, std::pair<int64_t, uint64_t>> per;
  for (const auto& e : c.events) {
    per[e.channel].first++;
    per[e.channel].second += e.data.size();
  }
  const double span = c.events.empty() ? 0.0 : 1e-6 * static_cast<double>(c.events.back().utime - c.events.front().utime);
  std::printf("%s: %zu events over %.3f s%s\n", path.c_str(), c.events.size(), span, c.damaged ? " (damaged)" : "");
  for (const auto& [ch, v] : per)
    std::printf("  %-26s %8lld events %10llu bytes\n", ch.c_str(), static_cast<long long>(v.first),
                static_cast<unsigned long long>(v.second));
  for (const auto& e : c.events)
    if (e.channel == igms::channels::kSessionInfo) {
      igms::session_info_t s;
      if (igms::safeDecode(e.data.data(), e.data.size(), &s))
        std::printf("  session: scene %s, model %s (hash %s), %s clock, dt %g s, %s\n", s.scene_path.c_str(),
                    s.model_path.c_str(), s.model_hash.c_str(), s.clock.c_str(), s.dt, s.build_version.c_str());
      break;
    }
  return c.damaged ? 3 : 0;
}

struct PlayOptions {
  double speed = 1.0, start = 0.0, end = 1e300;
  bool fast = false, loop = false, step = false;
  std::string regex = ".*", url;
  std::vector<std::string> remaps;  // FROM=TO
  std::string key_file;              // re-sign every event as a replay (a keyed bus)
  bool with_commands = false;        // publish the log's commands too
};

// A command: on the command channel, or anything that decodes as one (a crafted log may rename it).
bool isCommand(const std::string& channel, const std::vector<uint8_t>& data) {
  if (channel == igms::channels::kCommand) return true;
  int64_t hash = 0;
  if (data.size() >= 8)
    for (size_t k = 0; k < 8; ++k) hash = static_cast<int64_t>(static_cast<uint64_t>(hash) << 8 | data[k]);
  return hash == igms::command_t::getHash();
}

// What `igms-replay play` published and what it left out, by reason.
struct PlayCounts {
  int64_t published = 0, refused_skipped = 0, commands_skipped = 0, forged_skipped = 0, unsigned_published = 0;
};

void reportPlayed(const PlayCounts& n, bool keyed) {
  std::fprintf(stderr, "igms-replay: published %lld events%s\n", static_cast<long long>(n.published),
               keyed ? ", signed as a replay with the bus key (taken by servers, clients and devices only with "
                       "--accept-replay)"
                     : "");
  if (n.commands_skipped)
    std::fprintf(stderr, "igms-replay: left out %lld commands (--with-commands to publish them)\n",
                 static_cast<long long>(n.commands_skipped));
  if (n.forged_skipped)
    std::fprintf(stderr, "igms-replay: left out %lld events whose recorded signature does not hold under the key\n",
                 static_cast<long long>(n.forged_skipped));
  if (n.unsigned_published)
    std::fprintf(stderr, "igms-replay: %lld events were unsigned when recorded (an unauthenticated session)\n",
                 static_cast<long long>(n.unsigned_published));
  if (n.refused_skipped)
    std::fprintf(stderr, "igms-replay: left out %lld events the logger had refused (REFUSED:...)\n",
                 static_cast<long long>(n.refused_skipped));
}

int play(const std::string& path, const PlayOptions& o) {
  std::map<std::string, std::string> remap;
  for (const auto& r : o.remaps) remap[r.substr(0, r.find('='))] = r.substr(r.find('=') + 1);
  const auto c = load(path);
  if (c.events.empty()) return 1;
  std::optional<igms::bus::BusKey> key;
  try {
    key = igms::bus::busKeyFor("igms-replay", o.key_file);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-replay: %s\n", e.what());
    return 2;
  }
  lcm::LCM bus(o.url.empty() ? igms::channels::kDefaultUrl : o.url);
  if (!bus.good()) {
    std::fprintf(stderr, "igms-replay: cannot open LCM at %s\n", o.url.c_str());
    return 2;
  }
  // A replay is a sender of its own kind: the recorded signature comes off once it has been checked, and with a
  // key a replay's goes on, so a program that acts on the bus takes it only when told to (--accept-replay).
  igms::bus::SignedPublisher out(bus, key, 64 * 1024, igms::bus::SenderKind::kReplay);
  igms::bus::MessageVerifier recorded(key, "igms-replay");
  PlayCounts n;
  const std::regex filter(o.regex);
  const double speed = o.speed, start = o.start, end = o.end;
  const bool fast = o.fast, loop = o.loop, step = o.step;
  const int64_t t0 = c.events.front().utime;
  do {
    const auto wall0 = std::chrono::steady_clock::now();
    const double first = start;
    for (const auto& e : c.events) {
      if (igms::stopRequested()) break;
      const double t = 1e-6 * static_cast<double>(e.utime - t0);
      if (t < start || t > end || !std::regex_match(e.channel, filter)) continue;
      if (e.channel.rfind("REFUSED:", 0) == 0) {  // refused when recorded: never onto a real channel
        ++n.refused_skipped;
        continue;
      }
      auto it = remap.find(e.channel);
      const std::string& to = it == remap.end() ? e.channel : it->second;
      if (!o.with_commands && (isCommand(e.channel, e.data) || isCommand(to, e.data))) {
        ++n.commands_skipped;
        continue;
      }
      igms::bus::Trailer trailer;
      const bool had_trailer = igms::bus::findTrailer(e.data.data(), e.data.size(), &trailer);
      if (key && had_trailer && !recorded.tagHolds(e.channel, e.data.data(), e.data.size())) {
        ++n.forged_skipped;  // signed under another key, or altered since: not ours to sign
        continue;
      }
      if (step) {
        std::fprintf(stderr, "igms-replay: t=%.6f %s (%zu bytes) [enter]", t, e.channel.c_str(), e.data.size());
        std::string line;
        if (!std::getline(std::cin, line)) break;
      } else if (!fast) {
        std::this_thread::sleep_until(wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>((t - first) / speed)));
      }
      const size_t size = had_trailer ? trailer.payload_bytes : e.data.size();
      out.publish(to, e.data.data(), size);
      if (key && !had_trailer) ++n.unsigned_published;
      ++n.published;
    }
  } while (loop && n.published > 0 && !igms::stopRequested());
  reportPlayed(n, key.has_value());
  if (n.published == 0 && !igms::stopRequested()) {
    const std::string until = end > 1e12 ? std::string("the end") : std::to_string(end) + " s";
    std::fprintf(stderr, "igms-replay: nothing in %s matched --channel '%s' between %.3f s and %s\n", path.c_str(),
                 o.regex.c_str(), start, until.c_str());
    return 1;
  }
  return c.damaged ? 3 : 0;
}

struct ResimOptions {
  double tolerance = 1e-9;
  bool require_identical = false, json = false;
  std::string base = ".";
};

int resim(const std::string& path, const ResimOptions& o) {
  const double tolerance = o.tolerance;
  const bool require_identical = o.require_identical, json = o.json;
  const std::string& base = o.base;
  const auto c = load(path);
  const igms::ResimResult r = igms::resimulate(c.events, base);
  if (!r.ok) {
    std::fprintf(stderr, "igms-replay: %s: %s\n", path.c_str(), r.error.c_str());
    return 1;
  }
  if (json) {
    nlohmann::json out = {{"steps", r.steps},
                          {"identical", r.identical},
                          {"max_deviation", r.max_deviation},
                          {"model_from_log", r.model_from_log},
                          {"robots", r.robots},
                          {"models_from_log", r.models_from_log},
                          {"mesh_differences", r.mesh_differences},
                          {"fields", nlohmann::json::object()}};
    for (const auto& d : r.deviations) out["fields"][d.field] = d.max_abs;
    std::printf("%s\n", out.dump().c_str());
  } else {
    std::printf("igms-replay: re-simulated %lld steps of %s (scene %s, recorded by %s)\n",
                static_cast<long long>(r.steps), path.c_str(), r.scene_path.c_str(), r.build_logged.c_str());
    if (r.robots > 1)
      std::printf("  models: the log's copies of %d of the scene's %d robots' models%s\n", r.models_from_log, r.robots,
                  r.models_from_log < r.robots ? " (an older log carries the first robot's only; the rest from the disk)"
                                               : "");
    else if (r.model_from_log)
      std::printf("  model: the log's copy of %s%s\n", r.scene_path.empty() ? "the model" : "the scene's model",
                  r.model_hash_now == "absent"            ? " (the file is not here)"
                  : r.model_hash_logged != r.model_hash_now ? " (the file here has changed since)"
                                                            : "");
    else if (r.model_hash_logged != r.model_hash_now)
      std::printf("  note: the model file changed since the recording (hash %s, now %s)\n",
                  r.model_hash_logged.c_str(), r.model_hash_now.c_str());
    for (const auto& m : r.mesh_differences) std::printf("  note: mesh %s\n", m.c_str());
    for (const auto& d : r.deviations)
      std::printf("  %-18s max |recorded - now| = %-12.3g at step %lld\n", d.field.c_str(), d.max_abs,
                  static_cast<long long>(d.at_seq));
    std::printf("  %s\n", r.identical ? "identical to the recording, bit for bit" : "differs from the recording");
    if (!r.error.empty()) std::printf("  stopped early: %s\n", r.error.c_str());
  }
  if (require_identical && !r.identical) return 1;
  if (r.max_deviation > tolerance) {
    std::fprintf(stderr, "igms-replay: deviation %.3g exceeds the tolerance %.3g\n", r.max_deviation, tolerance);
    return 1;
  }
  return c.damaged || !r.error.empty() ? 3 : 0;
}

// Contacts between a robot's link and a free body in the last step (a robot that touched a box).
int robotBodyContacts(const igms::Simulation& sim) {
  const igms::ContactModel* cm = sim.contactModel();
  if (!cm) return 0;
  const igms::Model& m = sim.model();
  auto kind = [&](int geom) {  // 0: fixed, 1: a robot, 2: a free body
    const int part = cm->geom(geom).part;
    if (part < 0) return 0;
    return m.parts[static_cast<size_t>(part)].free_body ? 2 : 1;
  };
  int n = 0;
  const igms::ContactSet& set = sim.contacts();
  for (int k = 0; k < set.n; ++k) n += kind(set[k].geom_a) + kind(set[k].geom_b) == 3;
  return n;
}

// The log's copy of a model file (session_info_t's or a robot_files_t's: the same fields) as dir/file.
template <typename Message>
bool writeLoggedModel(const std::string& dir, const std::string& file, const Message& m) {
  try {
    const std::string text =
        igms::inflateText(m.model_zlib.data(), m.model_zlib.size(), static_cast<size_t>(m.model_size), "the log's model");
    std::ofstream(dir + "/" + file) << text;
    return true;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-replay: %s: %s\n", m.model_path.c_str(), e.what());
    return false;
  }
}

// `igms-replay export`: the log's channels as CSV files in one folder, one writer per channel, and what
// only a re-simulation has (environment.csv, obstacles.csv).
class CsvExport {
 public:
  explicit CsvExport(const std::string& dir)
      : dir_(dir),
        states_(dir + "/states.csv"),
        inputs_(dir + "/inputs.csv"),
        client_(dir + "/client_status.csv"),
        server_(dir + "/server_status.csv"),
        hands_(dir + "/hands.csv") {
    for (std::ofstream* f : {&states_, &inputs_, &client_, &server_, &hands_}) igms::cli::roundTripDigits(*f);
    // Every file starts with its header (states.csv's depends on the robot: written with its first row).
    inputs_ << "utime,seq,mode,tip_x,tip_y,tip_z,contact_link,attach_link,client\n";
    client_ << "utime,cycles,rate_hz,rtt_us_p50,rtt_us_p99,deadline_misses,fallbacks,force_scale,max_force_step,"
               "rendered_fx,rendered_fy,rendered_fz,client,proxy_substep_limited\n";
    // One row per hand per state: every input a step consumed and the force that hand applied.
    hands_ << "t,seq,client,input_seq,mode,fx,fy,fz,tx,ty,tz,px,py,pz\n";
    server_ << "t,steps,rate_hz,step_us_p50,step_us_p99,overruns,inputs_received,inputs_rejected,collisions,"
               "first_collision_time,min_obstacle_distance,commands_received,commands_rejected,contact_solves,"
               "contact_unconverged,contact_candidates_dropped,proxy_substep_limited,contact_slips_unturned,contact_linearised\n";
  }
  bool good() const { return static_cast<bool>(states_); }

  void events(const std::vector<igms::log::Event>& events) {
    for (const auto& e : events) {  // the state's link order, from any server status in the log
      igms::server_status_t st;
      if (e.channel == igms::channels::kServerStatus && igms::safeDecode(e.data.data(), e.data.size(), &st)) {
        links_ = st.link_names;
        break;
      }
    }
    for (const auto& e : events) {
      const auto* d = e.data.data();
      const int n = static_cast<int>(e.data.size());
      if (e.channel == igms::channels::kSessionInfo) sessionInfo(d, n);
      else if (e.channel == igms::channels::kSessionFiles && !wrote_models_) sessionFiles(d, n);
      else if (e.channel == igms::channels::kServerStatus) serverStatus(d, n);
      else if (e.channel == igms::channels::kRobotState) robotState(d, n);
      else if (e.channel == igms::channels::kHapticInput) hapticInput(d, n);
      else if (e.channel == igms::channels::kClientStatus) clientStatus(d, n);
    }
  }

  // An environment (free bodies, several robots, contact): environment.csv from the re-simulation
  // (bit-identical to the recorded run): every coordinate by name (each robot's q, each free body's
  // pose) and the step's contact count and deepest overlap, which the states do not carry. And
  // obstacles.csv: the robots' distance to each watched (not solid) obstacle on its own (the states
  // carry only the nearest), so that a summary can leave out the obstacle a line is meant to reach.
  void resimulated(const igms::Simulation& sim) {
    const auto& scene_obstacles = sim.scene().obstacles;
    const bool watched = std::any_of(scene_obstacles.begin(), scene_obstacles.end(),
                                     [](const igms::Obstacle& o) { return !o.solid; });
    if (watched) obstacleDistances(sim);
    if (!sim.hasContacts() && sim.model().parts.size() < 2) return;
    if (!env_header_) {
      env_.open(dir_ + "/environment.csv");
      igms::cli::roundTripDigits(env_);
      env_ << "t,step";
      for (const std::string& n : igms::coordinateNames(sim.model())) env_ << "," << n;
      env_ << ",contacts,max_penetration,robot_body_contacts\n";
      env_header_ = true;
    }
    env_ << sim.time() << "," << sim.steps();
    for (int k = 0; k < sim.q().size(); ++k) env_ << "," << sim.q()[k];
    env_ << "," << sim.contacts().n << "," << sim.contacts().maxPenetration() << "," << robotBodyContacts(sim) << "\n";
  }
  bool wroteEnvironment() const { return env_header_; }
  // Messages that did not decode as their channel's type (a log recorded by another version, whose
  // type's fingerprint differs; or damage), by channel: left out of the CSVs, and said so.
  const std::map<std::string, int64_t>& undecodable() const { return undecodable_; }
  bool wroteObstacles() const { return obstacles_header_; }

 private:
  template <typename Message>
  bool decoded(const char* channel, const uint8_t* d, int n, Message* m) {
    if (igms::safeDecode(d, n, m)) return true;
    ++undecodable_[channel];
    return false;
  }
  void sessionInfo(const uint8_t* d, int n) {
    igms::session_info_t s;
    if (!decoded(igms::channels::kSessionInfo, d, n, &s)) return;
    std::ofstream(dir_ + "/scene.yaml") << s.scene_text;
    // The log's copy of the model, next to the scene: an export stands on its own too.
    std::string model_file = std::filesystem::path(s.model_path).filename().string();
    if (s.model_size <= 0 || !writeLoggedModel(dir_, model_file, s)) model_file.clear();
    std::ofstream(dir_ + "/session.txt") << "scene_path: " << s.scene_path << "\nmodel_path: " << s.model_path
                                         << "\nmodel_hash: " << s.model_hash << "\nmodel_file: " << model_file
                                         << "\nbuild: " << s.build_version << "\nclock: " << s.clock << "\n";
  }
  // Every robot's model (a scene of several): beside the scene, and listed in models.txt.
  void sessionFiles(const uint8_t* d, int n) {
    igms::session_files_t f;
    if (!decoded(igms::channels::kSessionFiles, d, n, &f)) return;
    wrote_models_ = true;
    std::ofstream list(dir_ + "/models.txt");
    for (const igms::robot_files_t& r : f.robots) {
      std::string file = std::filesystem::path(r.model_path).filename().string();
      if (!r.robot.empty() && f.robots.size() > 1) file = r.robot + "_" + file;
      if (!writeLoggedModel(dir_, file, r)) file.clear();
      list << (r.robot.empty() ? "-" : r.robot) << " " << file << " " << r.model_hash << " " << r.model_path << "\n";
    }
  }
  void serverStatus(const uint8_t* d, int n) {
    igms::server_status_t s;
    if (!decoded(igms::channels::kServerStatus, d, n, &s)) return;
    server_ << s.sim_time << "," << s.steps << "," << s.rate_hz << "," << s.step_us_p50 << "," << s.step_us_p99
            << "," << s.overruns << "," << s.inputs_received << "," << s.inputs_rejected << "," << s.collisions
            << "," << s.first_collision_time << "," << s.min_obstacle_distance << "," << s.commands_received << ","
            << s.commands_rejected << "," << s.contact_solves << "," << s.contact_unconverged << ","
            << s.contact_candidates_dropped << "," << s.proxy_substep_limited << "," << s.contact_slips_unturned
            << "," << s.contact_linearised << "\n";
  }
  void statesHeader(const igms::robot_state_t& s) {
    states_ << "t,seq,input_seq,mode";
    for (int j = 0; j < s.nq; ++j) states_ << ",q" << j;
    for (int j = 0; j < s.nv; ++j) states_ << ",v" << j;
    for (int j = 0; j < s.nv; ++j) states_ << ",qdd" << j;
    for (int j = 0; j < s.nv; ++j) states_ << ",tau" << j;
    states_ << ",fx,fy,fz,px,py,pz,min_obstacle_distance,in_collision,step_us,tx,ty,tz,nhands";
    for (int l = 0; l < s.nlinks; ++l) {
      const std::string name = l < static_cast<int>(links_.size()) ? links_[l] : "link" + std::to_string(l);
      states_ << "," << name << ".x," << name << ".y," << name << ".z";
    }
    states_ << "\n";
  }
  void robotState(const uint8_t* d, int n) {
    igms::robot_state_t s;
    if (!decoded(igms::channels::kRobotState, d, n, &s)) return;
    if (!states_header_) {
      statesHeader(s);
      states_header_ = true;
    }
    states_ << s.sim_time << "," << s.seq << "," << s.input_seq << "," << int{s.mode};
    for (double x : s.q) states_ << "," << x;
    for (double x : s.v) states_ << "," << x;
    for (double x : s.qdd) states_ << "," << x;
    for (double x : s.tau) states_ << "," << x;
    for (double x : s.interaction_force) states_ << "," << x;
    for (double x : s.interaction_point) states_ << "," << x;
    states_ << "," << s.min_obstacle_distance << "," << int{s.in_collision} << "," << s.step_us;
    for (double x : s.interaction_torque) states_ << "," << x;
    states_ << "," << s.nhands;
    for (size_t h = 0; h < static_cast<size_t>(s.nhands); ++h) {
      hands_ << s.sim_time << "," << s.seq << "," << s.hand_client[h] << "," << s.hand_input_seq[h] << ","
             << int{s.hand_mode[h]};
      for (double x : s.hand_force[h]) hands_ << "," << x;
      for (double x : s.hand_torque[h]) hands_ << "," << x;
      for (double x : s.hand_point[h]) hands_ << "," << x;
      hands_ << "\n";
    }
    for (const auto& p : s.link_poses) states_ << "," << p[0] << "," << p[1] << "," << p[2];
    states_ << "\n";
  }
  void hapticInput(const uint8_t* d, int n) {
    igms::haptic_input_t s;
    if (!decoded(igms::channels::kHapticInput, d, n, &s)) return;
    inputs_ << s.utime << "," << s.seq << "," << int{s.mode} << "," << s.tip_position[0] << "," << s.tip_position[1]
            << "," << s.tip_position[2] << "," << s.contact_link << "," << s.attach_link << "," << s.client_id << "\n";
  }
  void clientStatus(const uint8_t* d, int n) {
    igms::client_status_t s;
    if (!decoded(igms::channels::kClientStatus, d, n, &s)) return;
    client_ << s.utime << "," << s.cycles << "," << s.rate_hz << "," << s.rtt_us_p50 << "," << s.rtt_us_p99 << ","
            << s.deadline_misses << "," << s.fallbacks << "," << s.force_scale << "," << s.max_force_step << ","
            << s.rendered_force[0] << "," << s.rendered_force[1] << "," << s.rendered_force[2] << "," << s.client_id
            << "," << s.proxy_substep_limited << "\n";
  }
  void obstacleDistances(const igms::Simulation& sim) {
    if (!obstacles_header_) {
      obstacles_.open(dir_ + "/obstacles.csv");
      igms::cli::roundTripDigits(obstacles_);
      obstacles_ << "t,step";
      for (const igms::Obstacle& o : sim.scene().obstacles) {
        if (o.solid) continue;  // touched through contact, not watched (the states' distance leaves it out too)
        obstacles_ << "," << o.name;
        each_obstacle_.push_back(std::make_unique<igms::CollisionWorld>(
            sim.model(), sim.geometry(), [&o](const std::string& name) { return name == o.name; }));
      }
      obstacles_ << "\n";
      obstacles_header_ = true;
      fk_ = std::make_unique<igms::Data>(sim.model());
    }
    igms::forwardKinematics(sim.model(), *fk_, sim.q());  // every frame's world pose, in fk_->oMf
    obstacles_ << sim.time() << "," << sim.steps();
    for (const auto& world : each_obstacle_) obstacles_ << "," << world->check(fk_->oMf).min_distance;
    obstacles_ << "\n";
  }

  std::string dir_;
  std::ofstream states_, inputs_, client_, server_, hands_, env_, obstacles_;
  std::vector<std::string> links_;  // the state's link order
  bool states_header_ = false, wrote_models_ = false, env_header_ = false, obstacles_header_ = false;
  std::map<std::string, int64_t> undecodable_;
  std::vector<std::unique_ptr<igms::CollisionWorld>> each_obstacle_;
  std::unique_ptr<igms::Data> fk_;  // the link poses for the check (the callback's simulation is const)
};

int exportCsv(const std::string& path, const std::string& dir) {
  const auto c = load(path);
  std::error_code made;
  std::filesystem::create_directories(dir, made);  // out/x when out/ does not exist yet
  CsvExport out(dir);
  if (!out.good()) {
    std::fprintf(stderr, "igms-replay: cannot write to %s\n", dir.c_str());
    return 2;
  }
  out.events(c.events);
  const igms::ResimResult r = igms::resimulate(c.events, ".", [&](const igms::Simulation& sim) { out.resimulated(sim); });
  if (out.wroteEnvironment() && !r.error.empty())
    std::fprintf(stderr, "igms-replay: environment.csv: %s\n", r.error.c_str());
  for (const auto& [channel, count] : out.undecodable())
    std::fprintf(stderr, "igms-replay: left out %lld messages on %s that do not decode as its type (recorded by "
                 "another version of igms?)\n", static_cast<long long>(count), channel.c_str());
  std::fprintf(stderr, "igms-replay: exported %s to %s/%s%s\n", path.c_str(), dir.c_str(),
               out.wroteObstacles() ? " (with obstacles.csv)" : "", out.wroteEnvironment() ? " (with environment.csv)" : "");
  return c.damaged ? 3 : 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"", "igms-replay"};
  igms::cli::describe(app, "Plays back, re-simulates and exports igms session logs (.lcmlog or .lcmlog.gz). A damaged "
                           "log gives its byte offset; the events before the damage are used (exit code 3).");
  app.require_subcommand(1);
  std::string path, dir;
  auto* info_cmd = app.add_subcommand("info", "events per channel, the session");
  info_cmd->add_option("LOG", path, "the log")->required()->check(CLI::ExistingFile);
  PlayOptions play_options;
  auto* play_cmd = app.add_subcommand("play", "publish the log's events on the bus, timed");
  play_cmd->add_option("LOG", path, "the log")->required()->check(CLI::ExistingFile);
  play_cmd->add_option("--speed", play_options.speed, "times real time")->check(igms::cli::positive("X"));
  play_cmd->add_flag("--fast", play_options.fast, "as fast as possible");
  play_cmd->add_option("--channel", play_options.regex, "only these channels (a regular expression)");
  play_cmd->add_option("--key-file", play_options.key_file, igms::bus::kKeyFileHelp)
      ->envname(igms::bus::kKeyFileEnv);
  play_cmd->add_option("--remap", play_options.remaps, "publish channel FROM as TO (repeatable)")
      ->allow_extra_args(false)
      ->check(CLI::Validator([](std::string& r) { return r.find('=') == std::string::npos ? "wants FROM=TO" : ""; },
                             "FROM=TO"));
  play_cmd->add_option("--start", play_options.start, "from this time, s after the first event")
      ->check(igms::cli::Seconds);
  play_cmd->add_option("--end", play_options.end, "until this time, s after the first event")
      ->check(igms::cli::Seconds);
  play_cmd->add_flag("--loop", play_options.loop, "start again at the end");
  play_cmd->add_flag("--with-commands", play_options.with_commands,
                     "publish the log's commands too (left out by default: a replay must not stop or reload a server)");
  play_cmd->add_flag("--step", play_options.step, "one event per Enter");
  play_cmd->add_option("--lcm-url", play_options.url, "LCM URL")->check(igms::cli::LcmUrl);
  ResimOptions resim_options;
  auto* resim_cmd = app.add_subcommand("resim", "re-simulate the recorded session and compare, field by field");
  resim_cmd->add_option("LOG", path, "the log")->required()->check(CLI::ExistingFile);
  resim_cmd->add_option("--tolerance", resim_options.tolerance, "largest deviation that passes")
      ->check(igms::cli::nonNegative("T"));
  resim_cmd->add_flag("--require-identical", resim_options.require_identical, "fail unless bit for bit");
  resim_cmd->add_option("--base-dir", resim_options.base, "resolve the scene's relative paths from here");
  resim_cmd->add_flag("--json", resim_options.json, "one JSON object on stdout");
  auto* export_cmd = app.add_subcommand("export", "CSV files and the scene, for plots");
  export_cmd->add_option("LOG", path, "the log")->required()->check(CLI::ExistingFile);
  export_cmd->add_option("DIR", dir, "output folder")->required();
  if (const int code = igms::cli::parse(app, argc, argv); code >= 0) return code;
  igms::stopOnSignals();
  try {
    if (*info_cmd) return info(path);
    if (*play_cmd) return play(path, play_options);
    if (*resim_cmd) return resim(path, resim_options);
    return exportCsv(path, dir);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "igms-replay: %s\n", e.what());
    return 1;
  }
}
