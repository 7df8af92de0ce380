#include "layerlab/app/process_pool.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <map>

#include "layerlab/app/exit_status.h"
#include "layerlab/framework/error.h"
#include "layerlab/framework/interrupt.h"

extern char** environ;

namespace layerlab::app {

std::string SelfExecutable() {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error("cannot find this executable (/proc/self/exe): " + ec.message());
  return self.string();
}

bool EndedByInterrupt(int status) {
  return (WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) ||
         (WIFEXITED(status) && WEXITSTATUS(status) == kExitInterrupted);
}

namespace {

pid_t Spawn(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (int e = posix_spawn(&pid, args.front().c_str(), nullptr, nullptr, argv.data(), environ); e != 0)
    throw Error(args.front() + ": cannot start a child process: " + std::strerror(e));
  return pid;
}

}  // namespace

void RunProcessPool(const std::vector<std::vector<std::string>>& commands, int processes,
                    const std::function<void(size_t, int)>& ended) {
  size_t next = 0;
  std::map<pid_t, size_t> running;
  while (next < commands.size() || !running.empty()) {
    while (next < commands.size() && static_cast<int>(running.size()) < processes && !Interrupted()) {
      running[Spawn(commands[next])] = next;
      ++next;
    }
    if (running.empty()) break;  // interrupted before anything more started
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) continue;
      throw Error(std::string("waiting for the child processes: ") + std::strerror(errno));
    }
    auto it = running.find(pid);
    if (it == running.end()) continue;
    const size_t i = it->second;
    running.erase(it);
    ended(i, status);
  }
}

}  // namespace layerlab::app
