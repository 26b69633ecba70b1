// The browser view's parts without a browser: mesh paths resolved, URDF
// visuals parsed, the scene described for the page, the bus seen as frames
// (undecodable messages counted, lost peers flagged), and the web server's
// routes (no path outside the page, only registered meshes, the token) over
// real sockets on 127.0.0.1.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <websocketpp/client.hpp>
#include <websocketpp/config/asio_no_tls_client.hpp>

#include "channels.h"
#include "core/model_io/resource_path.h"
#include "core/model_io/urdf_loader.h"
#include "igms/robot_state_t.hpp"
#include "igms/server_status_t.hpp"
#include "tests/support/http_get.h"
#include "web/bus_view.h"
#include "web/session_scene.h"
#include "web/web_server.h"

namespace fs = std::filesystem;
namespace {

using igms::resolveResource;
using igms::test::httpGet;
using igms::test::httpStatus;

fs::path tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("igms_web_view_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

// A one-joint arm whose link1 has a mesh visual in a package, a coloured box
// visual and a cylinder collision; link2 has no geometry.
constexpr const char* kArm = R"(<robot name="arm">
  <material name="red"><color rgba="0.9 0.1 0.1 1"/></material>
  <link name="base"/>
  <link name="link1">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="package://armpkg/meshes/link1.stl" scale="0.001 0.001 0.001"/></geometry></visual>
    <visual><origin xyz="0 0 0.1"/><geometry><box size="0.1 0.2 0.3"/></geometry><material name="red"/></visual>
    <collision><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>
  </link>
  <link name="link2">
    <inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="link1"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
  <joint name="j2" type="revolute"><parent link="link1"/><child link="link2"/><origin xyz="0 0 0.4"/>
    <axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="10" velocity="3"/></joint>
</robot>)";

TEST(ResourcePath, PackageFileAndRelative) {
  const fs::path d = tempDir("resource");
  write(d / "ws/armpkg/meshes/link1.stl", "solid x\nendsolid x\n");
  write(d / "ws/armpkg/urdf/arm.urdf", kArm);
  const std::string urdf = (d / "ws/armpkg/urdf/arm.urdf").string();
  // Found from the description's ancestors without any environment.
  unsetenv("IGMS_PACKAGE_PATH");
  unsetenv("ROS_PACKAGE_PATH");
  EXPECT_EQ(resolveResource("package://armpkg/meshes/link1.stl", urdf).path,
            fs::canonical(d / "ws/armpkg/meshes/link1.stl").string());
  // Relative to the description's folder, and file://.
  EXPECT_EQ(resolveResource("../meshes/link1.stl", urdf).path, fs::canonical(d / "ws/armpkg/meshes/link1.stl").string());
  EXPECT_EQ(resolveResource("file://" + (d / "ws/armpkg/meshes/link1.stl").string(), urdf).path,
            fs::canonical(d / "ws/armpkg/meshes/link1.stl").string());
  // Missing: no path, and the candidates tried are named.
  const igms::ResourceResolution missing = resolveResource("package://nopkg/a.stl", urdf);
  EXPECT_TRUE(missing.path.empty());
  EXPECT_FALSE(missing.tried.empty());
  // IGMS_PACKAGE_PATH comes first.
  write(d / "other/armpkg/meshes/link1.stl", "solid y\nendsolid y\n");
  setenv("IGMS_PACKAGE_PATH", (d / "other").c_str(), 1);
  EXPECT_EQ(resolveResource("package://armpkg/meshes/link1.stl", urdf).path,
            fs::canonical(d / "other/armpkg/meshes/link1.stl").string());
  unsetenv("IGMS_PACKAGE_PATH");
}

TEST(UrdfVisuals, ShapesColoursAndMeshes) {
  const fs::path d = tempDir("visuals");
  write(d / "arm.urdf", kArm);
  const igms::Model m = igms::loadUrdfModel((d / "arm.urdf").string());
  const igms::Frame& link1 = m.frame(m.frameIndex("link1"));
  ASSERT_EQ(link1.visuals.size(), 2u);
  EXPECT_EQ(link1.visuals[0].geometry.kind, igms::CollisionShape::Kind::Mesh);
  EXPECT_EQ(link1.visuals[0].geometry.mesh_file, "package://armpkg/meshes/link1.stl");
  EXPECT_NEAR(link1.visuals[0].geometry.mesh_scale.x(), 0.001, 1e-12);
  EXPECT_FALSE(link1.visuals[0].has_color);
  EXPECT_EQ(link1.visuals[1].geometry.kind, igms::CollisionShape::Kind::Box);
  EXPECT_TRUE(link1.visuals[1].has_color);
  EXPECT_NEAR(link1.visuals[1].rgba[0], 0.9, 1e-6);  // urdfdom keeps colours as float
  EXPECT_NEAR(link1.visuals[1].geometry.placement.p.z(), 0.1, 1e-12);
  EXPECT_EQ(link1.collisions.size(), 1u);
  EXPECT_TRUE(m.frame(m.frameIndex("link2")).visuals.empty());
}

igms::session_info_t sessionFor(const fs::path& scene) {
  igms::session_info_t info{};
  info.session_token = 42;
  info.scene_path = scene.string();
  std::ifstream in(scene);
  info.scene_text.assign(std::istreambuf_iterator<char>(in), {});
  info.model_hash = "h";
  info.clock = "realtime";
  info.dt = 0.001;
  return info;
}

TEST(SessionScene, DescribesLinksObstaclesAndPaths) {
  const std::string source = std::getenv("IGMS_SOURCE_DIR") ? std::getenv("IGMS_SOURCE_DIR") : ".";
  std::vector<std::string> served;
  const igms::web::SessionScene s = igms::web::describeSession(
      sessionFor(fs::path(source) / "scenes/puma_obstacle.yaml"),
      [&](const std::string& f) { served.push_back(f); return "/mesh/0/x"; });
  ASSERT_EQ(s.error, "");
  const nlohmann::json h = nlohmann::json::parse(s.hello_json);
  EXPECT_EQ(h["type"], "hello");
  EXPECT_EQ(h["links"].size(), 8u);
  EXPECT_EQ(h["obstacles"].size(), 2u);
  EXPECT_EQ(h["nominal_path"].size(), 201u);
  EXPECT_NEAR(h["nominal_end"].get<double>(), 4.0, 1e-9);
  EXPECT_EQ(h["links"][static_cast<size_t>(h["traced_link"].get<int>())]["name"], "ee_link");
  EXPECT_EQ(h["links"][2]["geometry"], "collision");  // the PUMA has collision shapes only
  EXPECT_EQ(h["links"][2]["shapes"][0]["kind"], "cylinder");
  EXPECT_TRUE(served.empty());
  EXPECT_NEAR(h["push"]["k_p"].get<double>(), 2000.0, 1e-9);
}

// An environment: free bodies are links drawn as their shapes; solid obstacles and the ground
// (a plane) come as obstacles marked solid.
TEST(SessionScene, DescribesFreeBodiesSolidObstaclesAndTheGround) {
  const std::string source = std::getenv("IGMS_SOURCE_DIR") ? std::getenv("IGMS_SOURCE_DIR") : ".";
  const igms::web::SessionScene s = igms::web::describeSession(
      sessionFor(fs::path(source) / "scenes/puma_table.yaml"), [&](const std::string&) { return "/mesh/0/x"; });
  ASSERT_EQ(s.error, "");
  const nlohmann::json h = nlohmann::json::parse(s.hello_json);
  int boxes = 0;
  for (const auto& l : h["links"])
    if (l["name"].get<std::string>().rfind("box_", 0) == 0) {
      ++boxes;
      EXPECT_EQ(l["shapes"][0]["kind"], "box");  // a free body is drawn as its shape
    }
  EXPECT_EQ(boxes, 3);
  ASSERT_EQ(h["obstacles"].size(), 3u);  // the wall (a ghost), the table (solid), the ground
  EXPECT_FALSE(h["obstacles"][0]["solid"].get<bool>());
  EXPECT_TRUE(h["obstacles"][1]["solid"].get<bool>());
  EXPECT_EQ(h["obstacles"][2]["name"], "ground");
  EXPECT_EQ(h["obstacles"][2]["kind"], "plane");
  EXPECT_NEAR(h["obstacles"][2]["p"][2].get<double>(), -0.4, 1e-12);
}

// Several robots from several files: each robot's meshes resolve against its
// own file (the Go1's package:// meshes beside the PUMA once came out missing).
TEST(SessionScene, EachRobotsMeshesResolveAgainstItsOwnFile) {
  const std::string source = std::getenv("IGMS_SOURCE_DIR") ? std::getenv("IGMS_SOURCE_DIR") : ".";
  const igms::web::SessionScene s = igms::web::describeSession(
      sessionFor(fs::path(source) / "scenes/workcell.yaml"), [&](const std::string& p) { return "/mesh/" + p; });
  ASSERT_EQ(s.error, "");
  const nlohmann::json h = nlohmann::json::parse(s.hello_json);
  int meshes = 0;
  for (const auto& l : h["links"])
    for (const auto& shape : l["shapes"]) {
      if (shape["kind"] != "mesh") continue;
      ++meshes;
      EXPECT_FALSE(shape.contains("missing")) << l["name"] << ": " << shape.dump();
    }
  EXPECT_GE(meshes, 13) << "the Go1's trunk, hips, thighs and calves";
}

// Found by bus_fuzz_test: a session_info whose strings are not UTF-8 made the
// hello's JSON throw, which ended igms-viewer. Now the bytes become U+FFFD.
TEST(SessionScene, StringsThatAreNotUtf8DoNotThrow) {
  igms::session_info_t info = sessionFor("/nonexistent/\xfa\xfb.yaml");
  info.build_version = "\xff\xfe";
  info.scene_text = "name: \xfa\n";
  igms::web::SessionScene s;
  ASSERT_NO_THROW(s = igms::web::describeSession(info, [](const std::string&) { return "/x"; }));
  const nlohmann::json h = nlohmann::json::parse(s.hello_json);
  EXPECT_NE(h["build"].get<std::string>().find("\xef\xbf\xbd"), std::string::npos) << "U+FFFD in place of 0xFF";
  EXPECT_NE(s.error, "") << "and the scene error is named";
}

TEST(SessionScene, MeshesAreServedAndMissingOnesNamed) {
  const fs::path d = tempDir("scene");
  write(d / "armpkg/urdf/arm.urdf", kArm);
  write(d / "armpkg/meshes/link1.stl", "solid x\nendsolid x\n");
  write(d / "arm.yaml", "name: arm\nrobot: {model: armpkg/urdf/arm.urdf}\n");
  std::vector<std::string> served;
  igms::web::SessionScene s = igms::web::describeSession(
      sessionFor(d / "arm.yaml"), [&](const std::string& f) { served.push_back(f); return "/mesh/7/link1.stl"; });
  ASSERT_EQ(s.error, "");
  nlohmann::json h = nlohmann::json::parse(s.hello_json);
  const nlohmann::json& link1 = h["links"][1];
  EXPECT_EQ(link1["geometry"], "visual");
  EXPECT_EQ(link1["shapes"][0]["url"], "/mesh/7/link1.stl");
  EXPECT_NEAR(link1["shapes"][1]["rgba"][0].get<double>(), 0.9, 1e-6);
  EXPECT_EQ(h["links"][2]["geometry"], "none");
  EXPECT_EQ(h["links"][2]["parent"], 1);  // drawn as a stick from link1
  ASSERT_EQ(served.size(), 1u);
  EXPECT_EQ(served[0], fs::canonical(d / "armpkg/meshes/link1.stl").string());
  // Without the mesh: the scene still loads; the page is told what is missing.
  fs::remove(d / "armpkg/meshes/link1.stl");
  s = igms::web::describeSession(sessionFor(d / "arm.yaml"), [](const std::string&) { return "/x"; });
  h = nlohmann::json::parse(s.hello_json);
  EXPECT_EQ(h["links"][1]["shapes"][0]["missing"], "package://armpkg/meshes/link1.stl");
  // A scene that does not load: an error in the hello, no exception.
  s = igms::web::describeSession(sessionFor(d / "nothing.yaml"), [](const std::string&) { return "/x"; });
  EXPECT_NE(s.error, "");
}

std::vector<uint8_t> encodedState(int64_t seq, int nlinks) {
  igms::robot_state_t m{};
  m.seq = seq;
  m.sim_time = 0.001 * static_cast<double>(seq);
  m.nq = m.nv = 0;
  m.nlinks = nlinks;
  m.link_poses.assign(static_cast<size_t>(nlinks), std::vector<double>{1, 2, 3, 1, 0, 0, 0});
  m.closest_link = -1;
  std::vector<uint8_t> buf(static_cast<size_t>(m.getEncodedSize()));
  m.encode(buf.data(), 0, static_cast<int>(buf.size()));
  return buf;
}

TEST(BusView, FramesFromTheNewestStateAndLostPeers) {
  igms::web::BusView view;
  EXPECT_EQ(view.frameJson(0.0, ""), "");  // nothing yet: no frame
  const std::vector<uint8_t> a = encodedState(5, 3);
  view.handle(igms::channels::kRobotState, a.data(), a.size(), 10.0);
  const std::vector<uint8_t> b = encodedState(6, 3);
  view.handle(igms::channels::kRobotState, b.data(), b.size(), 10.001);
  const nlohmann::json f = nlohmann::json::parse(view.frameJson(10.1, ",\"extra\":1"));
  EXPECT_EQ(f["type"], "frame");
  EXPECT_EQ(f["seq"], 6);
  ASSERT_EQ(f["poses"].size(), 3u);
  EXPECT_EQ(f["poses"][2][0], 1);
  EXPECT_EQ(f["extra"], 1);
  EXPECT_FALSE(f["server_lost"].get<bool>());
  EXPECT_TRUE(nlohmann::json::parse(view.frameJson(11.5, ""))["server_lost"].get<bool>());
  // Garbage, a truncated state, a zero-length string: counted, never fatal, the last good state kept.
  const std::vector<uint8_t> junk(40, 0xff);
  view.handle(igms::channels::kRobotState, junk.data(), junk.size(), 12.0);
  view.handle(igms::channels::kRobotState, b.data(), b.size() / 2, 12.0);
  igms::server_status_t st{};
  st.state = "running";
  std::vector<uint8_t> sb(static_cast<size_t>(st.getEncodedSize()));
  st.encode(sb.data(), 0, static_cast<int>(sb.size()));
  sb[32] = sb[33] = sb[34] = sb[35] = 0;  // the scene string's length: 0 (LCM 1.3.1 throws on it)
  view.handle(igms::channels::kServerStatus, sb.data(), sb.size(), 12.0);
  EXPECT_EQ(view.undecodable(), 3);
  EXPECT_EQ(nlohmann::json::parse(view.frameJson(12.0, ""))["seq"], 6);
}

// The server's status rides in the frame, the contact solve's counts with it (the HUD's "contact
// solves" row: solves, those cut short, answers that kept a slip unturned).
TEST(BusView, TheServersContactSolveCountsInTheFrame) {
  igms::web::BusView view;
  const std::vector<uint8_t> a = encodedState(5, 2);
  view.handle(igms::channels::kRobotState, a.data(), a.size(), 10.0);
  igms::server_status_t st{};
  st.state = "running";
  st.contact_solves = 8000;
  st.contact_unconverged = 26;
  st.contact_slips_unturned = 247;
  std::vector<uint8_t> sb(static_cast<size_t>(st.getEncodedSize()));
  st.encode(sb.data(), 0, static_cast<int>(sb.size()));
  view.handle(igms::channels::kServerStatus, sb.data(), sb.size(), 10.0);
  const nlohmann::json f = nlohmann::json::parse(view.frameJson(10.1, ""));
  ASSERT_TRUE(f.contains("server")) << f.dump();
  EXPECT_EQ(f["server"]["state"], "running");
  EXPECT_EQ(f["server"]["contact"]["solves"], 8000);
  EXPECT_EQ(f["server"]["contact"]["unconverged"], 26);
  EXPECT_EQ(f["server"]["contact"]["slips_unturned"], 247);
}

// The contacts ride in the frame as flat point and force arrays while fresh,
// each force the one on the moving side; a malformed contacts message is
// counted and changes nothing.
TEST(BusView, ContactsInTheFrameWhileFresh) {
  igms::web::BusView view;
  const std::vector<uint8_t> a = encodedState(5, 2);
  view.handle(igms::channels::kRobotState, a.data(), a.size(), 10.0);
  igms::contacts_t c{};
  c.seq = 5;
  c.total = 3;
  c.ncontacts = 2;
  c.link_a = {-1, 1};
  c.link_b = {0, -1};  // the second: the body is side a, the ground side b
  c.point = {{0.1, 0.2, 0.0}, {0.3, 0.4, 0.0}};
  c.normal = {{0, 0, 1}, {0, 0, 1}};
  c.force = {{0, 0, 4.905}, {0.5, 0, 4.905}};
  c.distance = {-1e-4, 0.0};
  std::vector<uint8_t> cb(static_cast<size_t>(c.getEncodedSize()));
  c.encode(cb.data(), 0, static_cast<int>(cb.size()));
  view.handle(igms::channels::kContacts, cb.data(), cb.size(), 10.0);
  nlohmann::json f = nlohmann::json::parse(view.frameJson(10.1, ""));
  ASSERT_TRUE(f.contains("contacts")) << f.dump();
  EXPECT_EQ(f["contacts"]["total"], 3) << "more than sent: the total is the step's";
  ASSERT_EQ(f["contacts"]["p"].size(), 6u);
  ASSERT_EQ(f["contacts"]["f"].size(), 6u);
  EXPECT_DOUBLE_EQ(f["contacts"]["p"][3].get<double>(), 0.3);
  EXPECT_DOUBLE_EQ(f["contacts"]["f"][2].get<double>(), 4.905) << "on the body, side b";
  EXPECT_DOUBLE_EQ(f["contacts"]["f"][3].get<double>(), -0.5) << "on the body, side a: the force sent, reversed";
  // Junk and a count beyond what any server sends: counted, the last good contacts kept.
  const std::vector<uint8_t> junk(60, 0xff);
  view.handle(igms::channels::kContacts, junk.data(), junk.size(), 10.1);
  c.ncontacts = igms::web::BusView::kMaxContacts + 1;
  c.link_a.assign(static_cast<size_t>(c.ncontacts), -1);
  c.link_b.assign(static_cast<size_t>(c.ncontacts), 0);
  c.point.assign(static_cast<size_t>(c.ncontacts), {0, 0, 0});
  c.normal = c.force = c.point;
  c.distance.assign(static_cast<size_t>(c.ncontacts), 0.0);
  std::vector<uint8_t> big(static_cast<size_t>(c.getEncodedSize()));
  c.encode(big.data(), 0, static_cast<int>(big.size()));
  view.handle(igms::channels::kContacts, big.data(), big.size(), 10.1);
  EXPECT_EQ(view.undecodable(), 2);
  f = nlohmann::json::parse(view.frameJson(10.2, ""));
  EXPECT_EQ(f["contacts"]["p"].size(), 6u);
  // Stale: no longer drawn.
  f = nlohmann::json::parse(view.frameJson(10.0 + igms::web::BusView::kContactsFor + 0.01, ""));
  EXPECT_FALSE(f.contains("contacts"));
}

// --- the web server over real sockets ---

// Opens /ws (with `query`), sends `text`, waits for the server's first
// message; returns what the server's open handler saw.
struct WsResult {
  bool opened = false;
  std::string first_message;
  std::vector<std::string> messages;  // all it was sent within the session
  bool said(const std::string& m) const { return std::find(messages.begin(), messages.end(), m) != messages.end(); }
};

// Opens /ws with `origin` (none when empty), sends `texts` in order, and collects what comes back for
// up to 300 ms (or until `until` arrives).
WsResult wsSession(int port, const std::vector<std::string>& texts, const std::string& origin,
                   const std::string& until = "") {
  using Client = websocketpp::client<websocketpp::config::asio_client>;
  Client c;
  c.clear_access_channels(websocketpp::log::alevel::all);
  c.clear_error_channels(websocketpp::log::elevel::all);
  c.init_asio();
  WsResult r;
  std::mutex mutex;
  c.set_open_handler([&](websocketpp::connection_hdl h) {
    r.opened = true;
    websocketpp::lib::error_code ec;
    for (const std::string& text : texts) c.send(h, text, websocketpp::frame::opcode::text, ec);
  });
  c.set_message_handler([&](websocketpp::connection_hdl, Client::message_ptr m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (r.first_message.empty()) r.first_message = m->get_payload();
    r.messages.push_back(m->get_payload());
  });
  websocketpp::lib::error_code ec;
  Client::connection_ptr con = c.get_connection("ws://127.0.0.1:" + std::to_string(port) + "/ws", ec);
  if (ec) return r;
  if (!origin.empty()) con->replace_header("Origin", origin);
  c.connect(con);
  std::thread t([&] { c.run(); });
  for (int i = 0; i < 30; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::lock_guard<std::mutex> lock(mutex);
    if (!until.empty() && r.said(until)) break;
  }
  c.stop();
  t.join();
  return r;
}

TEST(WebServer, AWebSocketMustComeFromThePagesOwnOrigin) {
  using igms::web::sameOrigin;
  // Not a browser (no Origin): only when allowed (issue 44: an empty Origin had been taken).
  EXPECT_FALSE(sameOrigin("", "127.0.0.1:8081", "127.0.0.1", 8081));
  EXPECT_TRUE(sameOrigin("", "127.0.0.1:8081", "127.0.0.1", 8081, /*allow_no_origin=*/true));
  EXPECT_TRUE(sameOrigin("http://127.0.0.1:8081", "127.0.0.1:8081", "127.0.0.1", 8081));
  EXPECT_TRUE(sameOrigin("http://localhost:8081", "localhost:8081", "127.0.0.1", 8081));
  EXPECT_FALSE(sameOrigin("http://evil.example", "127.0.0.1:8081", "127.0.0.1", 8081));
  EXPECT_FALSE(sameOrigin("http://127.0.0.1:8080", "127.0.0.1:8081", "127.0.0.1", 8081));  // another port: another site
  EXPECT_FALSE(sameOrigin("null", "127.0.0.1:8081", "127.0.0.1", 8081));  // a sandboxed or file:// page
  // DNS rebinding: a name that resolves to 127.0.0.1 is still not this machine's page.
  EXPECT_FALSE(sameOrigin("http://rebind.example:8081", "rebind.example:8081", "127.0.0.1", 8081));
  // Served on the LAN (--bind 0.0.0.0): the page's own host, whatever its name.
  EXPECT_TRUE(sameOrigin("http://lab-pc:8081", "lab-pc:8081", "0.0.0.0", 8081));
  EXPECT_FALSE(sameOrigin("http://evil.example", "lab-pc:8081", "0.0.0.0", 8081));
}

TEST(WebServer, TheHostMustBeANameTheServerIsBoundTo) {
  using igms::web::hostAllowed;
  for (const char* host : {"127.0.0.1:8081", "127.0.0.1", "localhost:8081", "localhost", "[::1]:8081", "[::1]"})
    EXPECT_TRUE(hostAllowed(host, "127.0.0.1", 8081)) << host;
  for (const char* host : {"rebind.example:8081", "rebind.example", "127.0.0.1:8080", "", "[::1", "10.0.0.5:8081"})
    EXPECT_FALSE(hostAllowed(host, "127.0.0.1", 8081)) << host;
  EXPECT_TRUE(hostAllowed("10.0.0.5:8081", "10.0.0.5", 8081));  // bound to one address: that one
  EXPECT_FALSE(hostAllowed("localhost:8081", "10.0.0.5", 8081));
  EXPECT_TRUE(hostAllowed("lab-pc:8081", "0.0.0.0", 8081));  // bound to every address: any name
}

TEST(WebServer, RoutesTokenAndCounters) {
  const fs::path d = tempDir("server");
  write(d / "page/index.html", "<html>igms page</html>");
  write(d / "page/main.js", "export {};");
  write(d / "three/build/three.module.js", "export const REVISION = '111';");
  write(d / "secret.txt", "not for pages");
  write(d / "meshes/link1.stl", "solid x\nendsolid x\n");
  igms::web::WebServerOptions o;
  o.page_dir = (d / "page").string();
  o.three_dir = (d / "three").string();
  o.token = "abc123";
  igms::web::WebServer server(o);
  std::atomic<int> opened{0}, authorized{0}, messages{0}, authorized_messages{0};
  server.onOpen([&](int client, bool is_authorized) {
    EXPECT_FALSE(is_authorized) << "no page is the device before its first message";
    ++opened;
    server.send(client, "viewer");
  });
  server.onAuthorized([&](int client) {
    ++authorized;
    server.send(client, "device");
  });
  server.onMessage([&](int, bool is_authorized, const std::string&) {
    ++messages;
    if (is_authorized) ++authorized_messages;
  });
  server.start();
  const int port = server.port();
  ASSERT_GT(port, 0);
  EXPECT_EQ(server.url(true), "http://127.0.0.1:" + std::to_string(port) + "/#token=abc123");
  const std::string own = "http://127.0.0.1:" + std::to_string(port);

  std::string r = httpGet(port, "/");
  EXPECT_EQ(httpStatus(r), 200);
  EXPECT_NE(r.find("igms page"), std::string::npos);
  r = httpGet(port, "/igms/main.js");
  EXPECT_EQ(httpStatus(r), 200);
  EXPECT_NE(r.find("application/javascript"), std::string::npos);  // module scripts need it
  EXPECT_EQ(httpStatus(httpGet(port, "/three/build/three.module.js")), 200);
  // Nothing outside the page and three.js, however the path is spelled.
  EXPECT_EQ(httpStatus(httpGet(port, "/igms/../secret.txt")), 404);
  EXPECT_EQ(httpStatus(httpGet(port, "/igms/%2e%2e/secret.txt")), 404);
  EXPECT_EQ(httpStatus(httpGet(port, "/three/../../secret.txt")), 404);
  EXPECT_EQ(httpStatus(httpGet(port, "/etc/passwd")), 404);
  // Meshes only once registered, and only that file.
  EXPECT_EQ(httpStatus(httpGet(port, "/mesh/0/link1.stl")), 404);
  const std::string mesh = server.addFile((d / "meshes/link1.stl").string());
  EXPECT_EQ(server.addFile((d / "meshes/link1.stl").string()), mesh);  // once per file
  r = httpGet(port, mesh);
  EXPECT_EQ(httpStatus(r), 200);
  EXPECT_NE(r.find("solid x"), std::string::npos);

  // The token, as the socket's first message, makes the page the device; every other message is counted.
  const std::string auth = R"({"type":"auth","token":"abc123"})", wrong = R"({"type":"auth","token":"wrong"})";
  const WsResult device = wsSession(port, {auth, "{}"}, own, "device");
  EXPECT_EQ(device.first_message, "viewer");
  EXPECT_TRUE(device.said("device"));
  EXPECT_FALSE(wsSession(port, {wrong, "{}"}, own).said("device"));
  EXPECT_FALSE(wsSession(port, {"{}"}, own).said("device"));
  // One try per socket, and only first: a wrong token then the right one, or the right one late, is no device.
  EXPECT_FALSE(wsSession(port, {wrong, auth}, own).said("device"));
  EXPECT_FALSE(wsSession(port, {"{}", auth}, own).said("device"));
  // The token in the URL is no longer read (issue 44: it leaked into logs and process lists).
  EXPECT_EQ(authorized.load(), 1);
  EXPECT_EQ(opened.load(), 5);
  for (int i = 0; i < 100 && messages.load() < 4; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(messages.load(), 4);
  EXPECT_EQ(authorized_messages.load(), 1);
  // Another site's page (its Origin) gets no WebSocket, token or not; nor does a client without an Origin.
  EXPECT_FALSE(wsSession(port, {auth}, "http://evil.example").opened);
  EXPECT_FALSE(wsSession(port, {auth}, "http://127.0.0.1:1").opened);
  EXPECT_FALSE(wsSession(port, {auth}, "").opened);
  EXPECT_TRUE(wsSession(port, {auth}, own, "device").said("device"));
  // Over the size limit: dropped (the connection closes), counted, the server goes on.
  wsSession(port, {std::string(64 * 1024, 'x')}, own);
  // DNS rebinding: another site's name for 127.0.0.1 in Host reads nothing (a page of that site would
  // send it); this server's own names, with or without its port, do.
  const std::string p = ":" + std::to_string(port);
  for (const std::string& host : std::vector<std::string>{"rebind.example" + p, "rebind.example", "127.0.0.1:1", "evil.example:80"}) {
    EXPECT_EQ(httpStatus(httpGet(port, "/status.json", host)), 403) << host;
    EXPECT_EQ(httpStatus(httpGet(port, mesh, host)), 403) << host;
  }
  for (const std::string& host : std::vector<std::string>{"127.0.0.1" + p, "localhost" + p, "localhost", "[::1]" + p})
    EXPECT_EQ(httpStatus(httpGet(port, "/status.json", host)), 200) << host;
  const nlohmann::json s = nlohmann::json::parse(igms::test::httpBody(httpGet(port, "/status.json")));
  EXPECT_EQ(httpStatus(httpGet(port, "/status.json", "")), 400) << "no Host: the HTTP layer refuses it first";
  EXPECT_EQ(s["rejected_host"].get<int>(), 8);
  EXPECT_GE(s["http_not_found"].get<int>(), 5);
  EXPECT_EQ(s["messages"].get<int>(), 10);  // the oversized one closes its socket before it is a message
  EXPECT_EQ(s["rejected_origin"].get<int>(), 3);
  EXPECT_EQ(s["rejected_token"].get<int>(), 4);  // wrong, wrong then right, right but late (x2 counted: wrong, late)
  EXPECT_EQ(s["rejected_malformed"].get<int>(), 1);
  EXPECT_EQ(httpStatus(httpGet(port, "/")), 200);
}

TEST(WebServer, AClientWithoutAnOriginOnlyWhenAllowed) {
  const fs::path d = tempDir("no_origin");
  write(d / "page/index.html", "<html></html>");
  igms::web::WebServerOptions o;
  o.page_dir = (d / "page").string();
  o.three_dir = (d / "three").string();
  o.allow_no_origin = true;  // --allow-no-origin: a script of one's own
  igms::web::WebServer server(o);
  server.onOpen([&](int client, bool) { server.send(client, "viewer"); });
  server.start();
  EXPECT_TRUE(wsSession(server.port(), {"{}"}, "").opened);
  EXPECT_EQ(server.counters().rejected_origin.load(), 0);
}

TEST(WebServer, APageThatMayActIsServedOnThisMachineOnly) {
  igms::web::WebServerOptions o;
  o.token = "abc123";
  o.bind = "0.0.0.0";
  igms::web::WebServer server(o);
  try {
    server.start();
    FAIL() << "a page with a token was served on every address, without TLS";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("SSH tunnel"), std::string::npos) << e.what();
  }
  igms::web::WebServerOptions lan;  // watch-only (no token): the LAN may watch
  lan.bind = "10.255.255.1";  // not this machine's: refused by the system, not by the token rule
  igms::web::WebServer watch(lan);
  try {
    watch.start();
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()).find("SSH tunnel"), std::string::npos) << e.what();
  }
}

}  // namespace
