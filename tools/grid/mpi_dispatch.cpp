#include "mpi_dispatch.hpp"

#include <mpi.h>

#include <chrono>
#include <deque>
#include <stdexcept>

namespace dynweigh::tools::grid {
namespace {

enum Tag : int { kReady = 1, kRow = 2, kJob = 3, kStop = 4 };
// Each rank holds two jobs: it starts the next while its last row travels to rank 0 and rank 0
// answers, so it never waits on the dispatcher, which may then sleep between looks.
constexpr int kJobsInHand = 2;
constexpr std::chrono::microseconds kIdleWait{5000};

struct Message {
  int source = 0;
  int tag = 0;
  std::string text;
};

Message receive(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_CHAR, &count);
  Message message{probed.MPI_SOURCE, probed.MPI_TAG, std::string(std::size_t(count), '\0')};
  MPI_Recv(message.text.data(), count, MPI_CHAR, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return message;
}

void send(const std::string& text, int destination, Tag tag) {
  MPI_Send(text.data(), int(text.size()), MPI_CHAR, destination, tag, MPI_COMM_WORLD);
}

std::size_t job_number(const std::string& text, std::size_t jobs) {
  std::size_t used = 0;
  const unsigned long long job = std::stoull(text, &used);
  if (used == 0 || job >= jobs) throw std::runtime_error("a message names job '" + text + "' of none");
  return std::size_t(job);
}

// A row from another rank: "<job>\n<key>\n<row>".
void take_row(const Message& message, const std::vector<std::string>& keys, RowCollector& collector) {
  const auto first = message.text.find('\n');
  const auto second = message.text.find('\n', first + 1);
  if (first == std::string::npos || second == std::string::npos) {
    throw std::runtime_error("rank " + std::to_string(message.source) + " sent a malformed row");
  }
  const std::size_t job = job_number(message.text.substr(0, first), keys.size());
  if (message.text.compare(first + 1, second - first - 1, keys[job]) != 0) {
    throw std::runtime_error("rank " + std::to_string(message.source) + " runs another grid (job " +
                             std::to_string(job) + " is not '" + keys[job] + "' there): same options on every rank");
  }
  collector.accept(job, message.text.substr(second + 1), message.source);
}

}  // namespace

void deal_out_jobs(const ParallelSession& session, const std::vector<std::string>& keys, JobQueue& queue,
                   const ComputeRow& compute, RowCollector& collector) {
  LocalWorkers own(queue, compute, session.writer_may_compute() ? 1u : 0u);
  std::vector<int> in_hand(std::size_t(session.size()), 0);  // jobs dealt to a rank, rows not yet back
  int serving = session.size() - 1;
  while (serving > 0 || collector.missing() > 0) {
    bool busy = false;
    int arrived = 0;
    MPI_Status status;
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
    if (arrived) {
      busy = true;
      const Message message = receive(status);
      int& dealt = in_hand[std::size_t(message.source)];
      if (message.tag == kRow) {
        take_row(message, keys, collector);
        --dealt;
      }
      for (std::size_t job = 0; dealt < kJobsInHand && queue.take(job); ++dealt) {
        send(std::to_string(job), message.source, kJob);
      }
      if (dealt == 0) {
        send("", message.source, kStop);
        --serving;
      }
    }
    // Idle, sleep on our own thread's rows rather than spin on the probe: this thread must not
    // take a core from the computing ones (short timed sleeps are dear in a virtual machine). The
    // other ranks do not wait for it: each holds its next job already.
    FinishedJob finished;
    while (own.next_finished(finished, busy ? std::chrono::microseconds(0) : kIdleWait)) {
      collector.accept(finished.job, std::move(finished.row));
      busy = true;
    }
  }
}

std::size_t serve_jobs(const std::vector<std::string>& keys, const ComputeRow& compute) {
  std::size_t computed = 0;
  std::deque<std::size_t> in_hand;
  bool stopped = false;
  send("", 0, kReady);
  for (;;) {
    // Take whatever rank 0 has dealt; block only with nothing left to compute.
    while (!stopped) {
      int arrived = 1;
      MPI_Status status;
      if (in_hand.empty()) {
        MPI_Probe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
      } else {
        MPI_Iprobe(0, MPI_ANY_TAG, MPI_COMM_WORLD, &arrived, &status);
      }
      if (!arrived) break;
      const Message message = receive(status);
      if (message.tag == kStop) {
        stopped = true;
      } else {
        in_hand.push_back(job_number(message.text, keys.size()));
      }
    }
    if (in_hand.empty()) return computed;
    const std::size_t job = in_hand.front();
    in_hand.pop_front();
    send(std::to_string(job) + "\n" + keys[job] + "\n" + compute(job), 0, kRow);
    ++computed;
  }
}

}  // namespace dynweigh::tools::grid
