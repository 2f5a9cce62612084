#pragma once
// The processes a grid runs on. Without MPI (the plain build) there is one process and its threads.
// Built with DYNWEIGH_MPI, joining the session joins the MPI job `mpirun -np N` or `srun` started
// (a plain start is a job of one rank): rank 0 is the writer, the only rank that prints results.
//
//   grid::ParallelSession session(true);       // MPI_Init_thread ... MPI_Finalize in the destructor
//   if (session.writer()) print(...);
namespace dynweigh::tools::grid {

class ParallelSession {
 public:
  // One process, threads only: never touches MPI, even in an MPI build.
  ParallelSession() = default;
  // join_mpi: join the MPI job when built with DYNWEIGH_MPI (no effect otherwise).
  explicit ParallelSession(bool join_mpi);
  ~ParallelSession();
  ParallelSession(const ParallelSession&) = delete;
  ParallelSession& operator=(const ParallelSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool writer() const { return rank_ == 0; }
  // More than one rank: the grid is dealt out over MPI.
  bool distributed() const { return size_ > 1; }
  // The writer may compute beside its dispatcher only if MPI allows threads next to the one that
  // calls MPI (MPI_THREAD_FUNNELED).
  bool writer_may_compute() const { return threads_beside_mpi_; }

  // Ends every rank of the job (MPI_Abort), so that no rank waits forever on one that failed.
  [[noreturn]] void abort(int exit_code) const;

 private:
  int rank_ = 0;
  int size_ = 1;
  bool threads_beside_mpi_ = true;
  bool finalize_ = false;  // this session initialised MPI, so it finalises it
};

}  // namespace dynweigh::tools::grid
