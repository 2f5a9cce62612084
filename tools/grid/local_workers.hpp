#pragma once
// The jobs still to compute, and the threads of this process computing them. Finished rows wait
// in a queue for the one thread that writes them (the caller's), so journal and output need no lock.
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace dynweigh::tools::grid {

using ComputeRow = std::function<std::string(std::size_t job)>;

struct FinishedJob {
  std::size_t job = 0;
  std::string row;
};

// Jobs to hand out, in the grid's order; shared by the local threads and the MPI dispatcher.
class JobQueue {
 public:
  explicit JobQueue(std::vector<std::size_t> jobs) : jobs_(jobs.begin(), jobs.end()) {}
  bool take(std::size_t& job);
  void clear();

 private:
  std::mutex mutex_;
  std::deque<std::size_t> jobs_;
};

class LocalWorkers {
 public:
  LocalWorkers(JobQueue& queue, const ComputeRow& compute, unsigned threads);
  ~LocalWorkers();  // joins the threads (after the queue is cleared when a job failed)
  LocalWorkers(const LocalWorkers&) = delete;
  LocalWorkers& operator=(const LocalWorkers&) = delete;

  // The next finished job, waiting at most `wait`; rethrows the first failure of a job.
  bool next_finished(FinishedJob& finished, std::chrono::microseconds wait);

 private:
  void work();

  JobQueue& queue_;
  const ComputeRow& compute_;
  std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<FinishedJob> finished_;
  std::exception_ptr failure_;
  std::vector<std::thread> threads_;
};

}  // namespace dynweigh::tools::grid
