// relightd tests: the Cornell box baked once per binary (one luminaire,
// "spot"), temporary files, and a daemon set up at a small frame size.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <string>

#include "cornell_fixture.h"
#include "daemon.h"

namespace relight::daemon::testing {

inline const std::string& CornellBake() {
  return test::BakedFixture("cornell_box", baker::DirectModeKind::kExact).bake_path;
}

inline std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::string ReadAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline DaemonConfig SmallConfig() {
  DaemonConfig c;
  c.bake_path = CornellBake();
  c.width = 96;
  c.height = 72;
  c.fps = 10;
  return c;
}

// Runs the daemon to its end on this thread.
inline Status RunToEnd(Daemon& d) {
  std::atomic<bool> stop{false}, reload{false};
  RELIGHT_RETURN_IF_ERROR(d.Start());
  return d.Run(stop, reload);
}

}  // namespace relight::daemon::testing
