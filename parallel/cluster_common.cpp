// What every build has of parallel/cluster.hpp, with or without MPI.
#include <cstdlib>

#include "parallel/cluster.hpp"

namespace hyfal {

int launcher_rank() {
  for (const char* var : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* s = std::getenv(var); s && *s) return std::atoi(s);
  return 0;
}

int launcher_size() {
  for (const char* var : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* s = std::getenv(var); s && *s) return std::max(1, std::atoi(s));
  return 1;
}

double peer_timeout_seconds() {
  if (const char* s = std::getenv("HYFAL_PEER_TIMEOUT_S"); s && *s) {
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end && *end == '\0' && v >= 2.0 && v < 1e9) return v;
  }
  return 30.0;
}

}  // namespace hyfal
