// Real servers (nginx, redis-server, as Debian installs them) started by a test on a free loopback port
// and stopped with it: the shared compile cache is tested against what teams run, never a mock.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "text_files.hpp"

namespace statepack::testing {

// A port nothing listens on now (the kernel's choice for a socket bound to port 0).
inline int free_loopback_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size);
  ::close(fd);
  return ntohs(address.sin_port);
}

inline bool accepts_connections(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(uint16_t(port));
  const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  ::close(fd);
  return ok;
}

class LoopbackServer {
 public:
  LoopbackServer() = default;
  LoopbackServer(const LoopbackServer&) = delete;
  LoopbackServer& operator=(const LoopbackServer&) = delete;
  ~LoopbackServer() { stop(); }

  // nginx serving (GET) and storing (WebDAV PUT) files under `dir`/root; PUT under /fails/ answers 500,
  // under /missing/ 404, and /no-put/ allows GET only (405 to PUT).
  bool start_nginx(const std::filesystem::path& dir) {
    port_ = free_loopback_port();
    std::filesystem::create_directories(dir / "root");
    const std::string d = dir.string(), port = std::to_string(port_);
    write_file(dir / "nginx.conf",
               "daemon off;\nmaster_process off;\npid " + d + "/nginx.pid;\nerror_log " + d +
                   "/error.log;\nevents { worker_connections 256; }\nhttp {\n  access_log off;\n"
                   "  client_body_temp_path " +
                   d + "/body;\n  proxy_temp_path " + d + "/proxy;\n  fastcgi_temp_path " + d +
                   "/fastcgi;\n  uwsgi_temp_path " + d + "/uwsgi;\n  scgi_temp_path " + d +
                   "/scgi;\n  server {\n    listen 127.0.0.1:" + port + ";\n    root " + d +
                   "/root;\n    client_max_body_size 256m;\n"
                   "    location / { dav_methods PUT; create_full_put_path on; }\n"
                   "    location /fails/ { if ($request_method = PUT) { return 500; } }\n"
                   "    location /missing/ { if ($request_method = PUT) { return 404; } }\n"
                   "    location /no-put/ { }\n  }\n}\n");
    return launch({"nginx", "-e", d + "/error.log", "-p", d, "-c", d + "/nginx.conf"}, dir / "nginx.out");
  }

  // redis-server without persistence, on a port of its own.
  bool start_redis(const std::filesystem::path& dir) {
    port_ = free_loopback_port();
    std::filesystem::create_directories(dir);
    return launch({"redis-server", "--port", std::to_string(port_), "--bind", "127.0.0.1", "--save", "",
                   "--appendonly", "no", "--dir", dir.string()},
                  dir / "redis.out");
  }

  int port() const { return port_; }
  void pause() const { ::kill(pid_, SIGSTOP); }  // accepts connections (the kernel does), answers nothing
  void resume() const { ::kill(pid_, SIGCONT); }
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGCONT);
    ::kill(pid_, SIGKILL);
    ::waitpid(pid_, nullptr, 0);
    pid_ = -1;
  }

 private:
  bool launch(const std::vector<std::string>& args, const std::filesystem::path& log) {
    pid_ = ::fork();
    if (pid_ == 0) {
      FILE* out = std::freopen(log.c_str(), "w", stdout);
      (void)out;
      ::dup2(STDOUT_FILENO, STDERR_FILENO);
      std::vector<char*> argv;
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execvp(argv[0], argv.data());
      ::_exit(127);
    }
    for (int i = 0; i < 500; ++i) {  // up to 5 s
      if (accepts_connections(port_)) return true;
      if (::waitpid(pid_, nullptr, WNOHANG) == pid_) return pid_ = -1, false;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
  }

  pid_t pid_ = -1;
  int port_ = 0;
};

}  // namespace statepack::testing
