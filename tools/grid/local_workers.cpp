#include "local_workers.hpp"

namespace dynweigh::tools::grid {

bool JobQueue::take(std::size_t& job) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (jobs_.empty()) return false;
  job = jobs_.front();
  jobs_.pop_front();
  return true;
}

void JobQueue::clear() {
  const std::lock_guard<std::mutex> lock(mutex_);
  jobs_.clear();
}

LocalWorkers::LocalWorkers(JobQueue& queue, const ComputeRow& compute, unsigned threads)
    : queue_(queue), compute_(compute) {
  for (unsigned i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

LocalWorkers::~LocalWorkers() {
  queue_.clear();  // on a failure elsewhere: finish the jobs in hand, start no other
  for (auto& thread : threads_) thread.join();
}

void LocalWorkers::work() {
  for (std::size_t job; queue_.take(job);) {
    try {
      FinishedJob finished{job, compute_(job)};
      const std::lock_guard<std::mutex> lock(mutex_);
      finished_.push_back(std::move(finished));
    } catch (...) {
      queue_.clear();
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!failure_) failure_ = std::current_exception();
    }
    ready_.notify_one();
  }
}

bool LocalWorkers::next_finished(FinishedJob& finished, std::chrono::microseconds wait) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait_for(lock, wait, [this] { return failure_ || !finished_.empty(); });
  if (failure_) std::rethrow_exception(failure_);
  if (finished_.empty()) return false;
  finished = std::move(finished_.front());
  finished_.pop_front();
  return true;
}

}  // namespace dynweigh::tools::grid
