// caustica command line: render, merge, denoise, devices, bench, generate, sky, diff, plot.
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <string>

#include "host/app/cli.h"
#include "host/app/rank_group.h"
#include "host/cl/runtime.h"
#include "host/error.h"
#ifdef CAUSTICA_WITH_MPI
#include "host/mpi/mpi_ranks.h"
#endif

using namespace caustica;

namespace {
// "rank 1 of 3: " under mpirun with several ranks, else "".
std::string rank_prefix(const RankGroup* ranks) {
  if (!ranks || ranks->size() <= 1) return "";
  return "rank " + std::to_string(ranks->rank()) + " of " + std::to_string(ranks->size()) + ": ";
}

}  // namespace

int main(int argc, char** argv) {
  const std::unique_ptr<Cli> cli = make_cli();

  // Under mpirun: the ranks (MPI starts here, and only under a launcher).
  std::unique_ptr<RankGroup> ranks;
#ifdef CAUSTICA_WITH_MPI
  try {
    ranks = MpiRanks::if_launched(&argc, &argv);
  } catch (const Error& e) {
    std::fprintf(stderr, "caustica: error: %s\n", e.what());
    return 1;
  }
#else
  // Started by mpirun without MPI built in, every rank would render the
  // whole image and write the same files.
  if (const char* size = std::getenv("OMPI_COMM_WORLD_SIZE"); size && std::atoi(size) > 1) {
    std::fprintf(stderr, "caustica: error: started by mpirun with %s ranks, but this caustica was built without MPI "
                         "(install libopenmpi-dev and build again: docs/distributed.md)\n", size);
    return 1;
  }
#endif
  cli->render.ranks = ranks.get();
  // A rank that fails ends the others (MPI_Abort): none waits forever in a
  // collective for it.
  auto failed = [&ranks]() -> int {
    if (ranks && ranks->size() > 1) {
      std::fflush(stderr);
      ranks->abort(1);
    }
    return 1;
  };
  // Parsing runs inside the try: option callbacks (--bvh, --exposure...)
  // throw caustica::Error for values they refuse, and an exception escaping
  // main would abort with "terminate called" instead of a message.
  try {
    if (const int status = parse_command_line(*cli, argc, argv); status >= 0) return status;
    return run_command(*cli);
  } catch (const Error& e) {
    std::fprintf(stderr, "caustica: error: %s%s\n", rank_prefix(ranks.get()).c_str(), e.what());
    return failed();
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "caustica: OpenCL error: %s%s (%s)\n", rank_prefix(ranks.get()).c_str(), e.what(),
                 cl_error_name(e.err()).c_str());
    return failed();
  } catch (const std::bad_alloc&) {
    // Every input size is bounded (host/limits.h); this is the machine's own limit.
    std::fprintf(stderr, "caustica: error: %sout of memory (std::bad_alloc): this machine cannot hold the request\n",
                 rank_prefix(ranks.get()).c_str());
    return failed();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "caustica: error: %s%s\n", rank_prefix(ranks.get()).c_str(), e.what());
    return failed();
  }
  return 0;
}
