// make_communicator: MPI under an MPI launcher when built with MPI, one process otherwise.
#include <cstdlib>

#include "libs/distributed/communicator.h"
#include "core/util/error.h"

namespace facetool {

#ifdef FACETOOL_HAVE_MPI
std::unique_ptr<Communicator> make_mpi_communicator();
bool built_with_mpi() { return true; }
#else
bool built_with_mpi() { return false; }
#endif

namespace {
bool under_mpi_launcher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}
}  // namespace

std::unique_ptr<Communicator> make_communicator() {
  if (!under_mpi_launcher()) return std::make_unique<SingleProcessCommunicator>();
#ifdef FACETOOL_HAVE_MPI
  return make_mpi_communicator();
#else
  throw Error(
      "this process was started by an MPI launcher (mpirun/srun) but facetool was built without "
      "MPI; install libopenmpi-dev (scripts/install-dependencies.sh) and rebuild, or run it "
      "without mpirun");
#endif
}

}  // namespace facetool
