// Cluster without MPI (CMake found none): a single process, and a clear error under mpirun.
#include "parallel/cluster.hpp"

namespace hyfal {

Cluster* Cluster::current() { return nullptr; }

std::unique_ptr<Cluster> Cluster::join_if_launched(int*, char***) {
  if (launcher_size() > 1)
    throw ClusterSetupError("this hyfal was built without MPI, so it cannot run as one of several ranks: install "
                          "libopenmpi-dev (scripts/setup.sh does) and rebuild, or run it as one process");
  return nullptr;
}

}  // namespace hyfal
