// relightd's systemd notifications (runtime/daemon/src/notify.h): a datagram
// socket of the test's own stands in for systemd's $NOTIFY_SOCKET and reads
// what is sent: READY=1 after the first frame, WATCHDOG=1 at a quarter of
// WatchdogSec, STOPPING=1; nothing at all without $NOTIFY_SOCKET. Then the
// relightd process itself, started as systemd would start it.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "daemon_test_support.h"
#include "notify.h"

extern char** environ;

namespace relight::daemon {
namespace {

// A bound AF_UNIX datagram socket in the test's temp folder.
class NotifySocket {
 public:
  explicit NotifySocket(const std::string& name) : path_(::testing::TempDir() + "/" + name) {
    unlink(path_.c_str());
    fd_ = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    EXPECT_LT(path_.size(), sizeof addr.sun_path);
    path_.copy(addr.sun_path, sizeof addr.sun_path - 1);
    EXPECT_EQ(bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
    const timeval tv{0, 200000};  // Receive() gives up after 0.2 s
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~NotifySocket() {
    close(fd_);
    unlink(path_.c_str());
  }
  const std::string& path() const { return path_; }
  // The next datagram, or "" after `tries` timeouts of 0.2 s.
  std::string Receive(int tries = 1) {
    char buf[512];
    for (int i = 0; i < tries; ++i) {
      const ssize_t n = recv(fd_, buf, sizeof buf, 0);
      if (n >= 0) return std::string(buf, static_cast<size_t>(n));
    }
    return "";
  }

 private:
  std::string path_;
  int fd_ = -1;
};

// Sets an environment variable for one scope.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) { setenv(name, value.c_str(), 1); }
  ~ScopedEnv() { unsetenv(name_); }

 private:
  const char* name_;
};

TEST(SystemdNotifier, ReadyAfterTheFirstFrameThenWatchdogAtAQuarterOfItsTimeout) {
  NotifySocket sock("notify_unit.sock");
  ScopedEnv socket_env("NOTIFY_SOCKET", sock.path());
  ScopedEnv watchdog_env("WATCHDOG_USEC", "400000");
  ScopedEnv pid_env("WATCHDOG_PID", std::to_string(getpid()));
  SystemdNotifier n;
  EXPECT_EQ(n.watchdog_period_us(), 100000);
  EXPECT_FALSE(n.ready_sent());

  n.OnFrame(1000000);
  EXPECT_TRUE(n.ready_sent());
  EXPECT_EQ(sock.Receive().rfind("READY=1\n", 0), 0u);
  EXPECT_EQ(sock.Receive(), "WATCHDOG=1");
  n.OnFrame(1050000);  // half a period later: no ping
  n.OnFrame(1100000);  // a period after the last: ping
  EXPECT_EQ(sock.Receive(), "WATCHDOG=1");
  n.OnFrame(1150000);
  n.Stopping();
  EXPECT_EQ(sock.Receive(), "STOPPING=1");  // nothing in between
}

TEST(SystemdNotifier, NoWatchdogForAnotherProcessAndNothingWithoutASocket) {
  {
    NotifySocket sock("notify_other.sock");
    ScopedEnv socket_env("NOTIFY_SOCKET", sock.path());
    ScopedEnv watchdog_env("WATCHDOG_USEC", "400000");
    ScopedEnv pid_env("WATCHDOG_PID", std::to_string(getpid() + 1));  // meant for someone else
    SystemdNotifier n;
    EXPECT_EQ(n.watchdog_period_us(), 0);
    n.OnFrame(0);
    n.OnFrame(10000000);
    EXPECT_EQ(sock.Receive().rfind("READY=1\n", 0), 0u);
    EXPECT_EQ(sock.Receive(), "");  // no watchdog pings
  }
  unsetenv("NOTIFY_SOCKET");
  SystemdNotifier quiet;  // not under systemd: every call is a no-op
  quiet.OnFrame(0);
  quiet.Stopping();
  EXPECT_TRUE(quiet.ready_sent());
}

TEST(SystemdNotifier, RelightdSendsReadyThenWatchdogAndStopping) {
  NotifySocket sock("notify_relightd.sock");
  std::vector<std::string> env = {"NOTIFY_SOCKET=" + sock.path(), "WATCHDOG_USEC=200000"};
  for (char** e = environ; *e != nullptr; ++e) {
    const std::string s(*e);
    if (s.rfind("NOTIFY_SOCKET=", 0) != 0 && s.rfind("WATCHDOG_", 0) != 0) env.push_back(s);
  }
  std::vector<std::string> args = {RELIGHTD_PATH, testing::CornellBake(), "--fps", "20", "--width", "64",
                                   "--height", "48"};
  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  for (std::string& e : env) envp.push_back(e.data());
  argv.push_back(nullptr);
  envp.push_back(nullptr);
  pid_t pid = -1;
  ASSERT_EQ(posix_spawn(&pid, RELIGHTD_PATH, nullptr, nullptr, argv.data(), envp.data()), 0);
  // The first frame can take a while under a loaded machine or a sanitizer.
  const std::string ready = sock.Receive(300);
  EXPECT_EQ(ready.rfind("READY=1\n", 0), 0u) << "got '" << ready << "'";
  EXPECT_EQ(sock.Receive(50), "WATCHDOG=1");
  EXPECT_EQ(sock.Receive(50), "WATCHDOG=1");  // frames keep flowing: so do pings
  kill(pid, SIGTERM);
  std::string m = sock.Receive(50);
  while (m == "WATCHDOG=1") m = sock.Receive(50);  // pings of frames still in flight
  EXPECT_EQ(m, "STOPPING=1");
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

}  // namespace
}  // namespace relight::daemon
