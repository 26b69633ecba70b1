// Who may command the server and where its files may be: the key or the
// session token, scene and output folders (.., absolute paths, symbolic
// links that lead out).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "server/loop/command_policy.h"

namespace igms {
namespace {

namespace fs = std::filesystem;

struct Folders {
  fs::path root, scenes, out;
  Folders() {
    root = fs::temp_directory_path() / ("igms_command_policy_" + std::to_string(getpid()));
    fs::remove_all(root);
    scenes = root / "scenes";
    out = root / "out";
    fs::create_directories(scenes);
    fs::create_directories(out);
    std::ofstream(scenes / "a.yaml") << "name: a\n";
    std::ofstream(root / "secret.yaml") << "name: secret\n";
    fs::create_directory_symlink(root, out / "up");  // a link that leads out of the output folder
  }
  ~Folders() { fs::remove_all(root); }
};

command_t command(int8_t kind, const std::string& auth, const std::string& text = "") {
  command_t c{};
  c.kind = kind;
  c.auth = auth;
  c.text = text;
  return c;
}

TEST(CommandPolicy, TheSessionTokenAuthorizesOnAnUnauthenticatedBus) {
  CommandPolicy p;
  command_t out;
  EXPECT_TRUE(authorizeCommand(command(command_t::PAUSE, "42"), 0, 42, p, &out).accepted);
  EXPECT_FALSE(authorizeCommand(command(command_t::PAUSE, ""), 0, 42, p, &out).accepted);
  EXPECT_FALSE(authorizeCommand(command(command_t::PAUSE, "420"), 0, 42, p, &out).accepted);
  const CommandResult r = authorizeCommand(command(command_t::PAUSE, "4"), 0, 42, p, &out);
  EXPECT_FALSE(r.accepted);
  EXPECT_NE(r.message.find("session token"), std::string::npos);
}

// Issue 44, item 2: a signed command carried no token, so one captured from an earlier run of the
// server (its signature fresh for a minute) was taken by the restarted server. It is now bound to the
// session twice: by the token, and by its signature's time against the server's start.
TEST(CommandPolicy, OnASignedBusACommandIsBoundToThisRunOfTheServer) {
  CommandPolicy p;
  p.signed_bus = true;
  p.started_us = 1'000'000'000;
  command_t out;
  EXPECT_TRUE(authorizeCommand(command(command_t::SHUTDOWN, "42"), p.started_us + 5, 42, p, &out).accepted);
  // Captured from the run before: its token, and signed before this run started.
  const CommandResult old = authorizeCommand(command(command_t::SHUTDOWN, "41"), p.started_us - 20'000'000, 42, p, &out);
  EXPECT_FALSE(old.accepted);
  EXPECT_NE(old.message.find("before this server started"), std::string::npos) << old.message;
  // Either one alone is refused too.
  EXPECT_FALSE(authorizeCommand(command(command_t::SHUTDOWN, "42"), p.started_us - 1, 42, p, &out).accepted);
  const CommandResult token = authorizeCommand(command(command_t::SHUTDOWN, ""), p.started_us + 5, 42, p, &out);
  EXPECT_FALSE(token.accepted);
  EXPECT_NE(token.message.find("session token"), std::string::npos) << token.message;
}

TEST(CommandPolicy, FilesStayInTheirFolders) {
  Folders f;
  CommandPolicy p;
  p.scene_dirs = {f.scenes.string()};
  p.output_dir = f.out.string();
  command_t out;
  // Scenes: by name in the folder, or an absolute path inside it.
  ASSERT_TRUE(authorizeCommand(command(command_t::LOAD_SCENE, "1", "a.yaml"), 0, 1, p, &out).accepted);
  EXPECT_EQ(out.text, (f.scenes / "a.yaml").string());
  EXPECT_TRUE(authorizeCommand(command(command_t::LOAD_SCENE, "1", (f.scenes / "a.yaml").string()), 0, 1, p, &out).accepted);
  for (const std::string& bad : std::vector<std::string>{"../secret.yaml", (f.root / "secret.yaml").string(), "/etc/passwd", "missing.yaml", ""})
    EXPECT_FALSE(authorizeCommand(command(command_t::LOAD_SCENE, "1", bad), 0, 1, p, &out).accepted) << bad;
  // Output: relative names land inside; .., absolute paths outside and links out are refused.
  ASSERT_TRUE(authorizeCommand(command(command_t::SAVE_TRAJECTORY, "1", "edited.yaml"), 0, 1, p, &out).accepted);
  EXPECT_EQ(out.text, (f.out / "edited.yaml").string());
  EXPECT_TRUE(authorizeCommand(command(command_t::SAVE_TRAJECTORY, "1", "sub/../e.yaml"), 0, 1, p, &out).accepted);
  for (const std::string& bad : std::vector<std::string>{"../x.yaml", "/tmp/x.yaml", "up/secret.yaml", "up/out/../x.yaml"})
    EXPECT_FALSE(authorizeCommand(command(command_t::SAVE_TRAJECTORY, "1", bad), 0, 1, p, &out).accepted) << bad;
  EXPECT_EQ(insideFolder("x", f.out.string(), f.out.string()), (f.out / "x").string());
  EXPECT_EQ(insideFolder(f.out.string(), "/", f.out.string()), f.out.string());
  EXPECT_EQ(insideFolder((f.root / "outside").string(), "/", f.out.string()), "");
  EXPECT_EQ(insideFolder((f.root / "out2/x").string(), "/", f.out.string()), "") << "a sibling with the same prefix";
}

}  // namespace
}  // namespace igms
