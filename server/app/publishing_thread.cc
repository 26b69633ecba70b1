#include "server/app/publishing_thread.h"

namespace igms {

void PublishingThread::start(bool threaded) {
  if (!threaded) return;
  thread_ = std::thread([this] {
    while (!done_) {
      pump();
      if (!ring_.beginRead()) ring_.waitForWrite(0.020);  // the status is due at least this often
    }
  });
}

void PublishingThread::pump() {
  status_.pumpSessionInfo();  // before any state: a log starts with it
  while (const Snapshot* s = ring_.beginRead()) {
    states_.publish(*s);
    contacts_.publish(*s);
    ring_.endRead();
  }
  status_.pumpStatus(states_.stats());
}

void PublishingThread::finish() {
  if (finished_) return;
  finished_ = true;
  done_ = true;
  ring_.wake();
  if (thread_.joinable()) thread_.join();
  pump();
  status_.publishStatus(states_.stats());
}

}  // namespace igms
