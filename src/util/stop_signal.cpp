// SPDX-License-Identifier: MIT
#include "util/stop_signal.hpp"

#include <csignal>
#include <signal.h>

namespace slidebeam {
namespace {

volatile std::sig_atomic_t received = 0;

extern "C" void on_stop_signal(int sig) {
  if (received == 0) received = sig;
  std::signal(sig, SIG_DFL);  // async-signal-safe; the next one takes the default action
}

}  // namespace

void install_stop_handlers() {
  received = 0;
  struct sigaction action = {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // interrupted system calls (writes) resume
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int stop_signal() { return received; }

int stop_signal(MPI_Comm comm) {
  int mine = received, any = 0;
  MPI_Allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

}  // namespace slidebeam
