// Communicator: what data-parallel training needs from the ranks of a job (sums, rank, abort).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace facetool {

// The trainer talks to the other ranks only through this interface, so the compute core has no
// MPI in it: SingleProcessCommunicator (one rank; every sum is the identity) and, when facetool
// is built with MPI, MpiCommunicator. Every rank must make the same calls in the same order.
class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Sums `values` element-wise over the ranks, in place, in double precision.
  virtual void allreduce_sum(std::vector<double>& values) = 0;
  // The same for float buffers (gradients), in place.
  virtual void allreduce_sum(float* values, int64_t count) = 0;
  // Ends every rank of the job with `message` (a rank that failed must not leave the others
  // waiting in a sum).
  [[noreturn]] virtual void abort(const std::string& message) = 0;
  virtual std::string describe() const = 0;  // e.g. "1 process", "MPI, 4 ranks"
};

class SingleProcessCommunicator final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  void allreduce_sum(std::vector<double>&) override {}
  void allreduce_sum(float*, int64_t) override {}
  [[noreturn]] void abort(const std::string& message) override;
  std::string describe() const override { return "1 process"; }
};

// MPI when this process was started by an MPI launcher (mpirun sets OMPI_COMM_WORLD_SIZE,
// PMI_SIZE or PMIX_RANK) and facetool was built with MPI; one process otherwise. Started by a
// launcher but built without MPI is an error (K copies would each train alone).
std::unique_ptr<Communicator> make_communicator();
bool built_with_mpi();

// Rows [begin, end) of a global batch of `batch` rows that rank `rank` of `size` takes: the
// first batch % size ranks take one row more.
std::pair<int64_t, int64_t> rank_rows(int64_t batch, int rank, int size);

}  // namespace facetool
