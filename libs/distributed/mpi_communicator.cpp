// MpiCommunicator: Communicator over MPI_COMM_WORLD (compiled only when CMake finds MPI).
#include <mpi.h>

#include <cstdlib>
#include <iostream>
#include <limits>

#include "libs/distributed/communicator.h"
#include "core/util/error.h"

namespace facetool {
namespace {

// Errors return codes instead of aborting inside MPI, so the message names what failed; a rank
// that dies makes Open MPI's launcher end the job (no rank waits forever in a sum).
void check_mpi(int code, const char* what) {
  if (code == MPI_SUCCESS) return;
  char text[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(code, text, &length);
  std::cerr << "error: " << what << " failed: " << std::string(text, length)
            << " (another rank probably stopped; resume from the last checkpoint)\n";
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::exit(1);
}

class MpiCommunicator final : public Communicator {
 public:
  MpiCommunicator() {
    int initialised = 0;
    MPI_Initialized(&initialised);
    if (!initialised) check_mpi(MPI_Init(nullptr, nullptr), "MPI_Init");
    MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    MPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiCommunicator() override {
    int finalised = 0;
    MPI_Finalized(&finalised);
    if (!finalised) MPI_Finalize();
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  void allreduce_sum(std::vector<double>& values) override {
    check(values.size() <= static_cast<size_t>(std::numeric_limits<int>::max()),
          "allreduce_sum: too many values");
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()),
                            MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD),
              "MPI_Allreduce");
  }
  void allreduce_sum(float* values, int64_t count) override {
    check(count <= std::numeric_limits<int>::max(), "allreduce_sum: too many values");
    check_mpi(MPI_Allreduce(MPI_IN_PLACE, values, static_cast<int>(count), MPI_FLOAT, MPI_SUM,
                            MPI_COMM_WORLD),
              "MPI_Allreduce");
  }
  [[noreturn]] void abort(const std::string& message) override {
    std::cerr << "error (rank " << rank_ << " of " << size_ << "): " << message << "\n";
    MPI_Abort(MPI_COMM_WORLD, 1);
    std::exit(1);
  }
  std::string describe() const override {
    return "MPI, " + std::to_string(size_) + (size_ == 1 ? " rank" : " ranks");
  }

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace

std::unique_ptr<Communicator> make_mpi_communicator() {
  return std::make_unique<MpiCommunicator>();
}

}  // namespace facetool
