#include "parallel/team.h"

#include <cstdio>
#include <cstdlib>
#include <string>

#ifdef CAPFLOW_HAVE_MPI
#include <mpi.h>
#endif

namespace capflow::parallel {

namespace {
bool g_started = false;
int g_rank = 0, g_size = 1;     // in the team (the world, or this rank's group)
int g_group = 0, g_groups = 1;  // split(): which group, how many
#ifdef CAPFLOW_HAVE_MPI
MPI_Comm g_comm = MPI_COMM_WORLD;  // the team's communicator
#endif

// The launcher's rank count, from its environment (Open MPI's mpirun, MPICH/PMI, a Slurm job
// step: srun): 1 when not launched.
int launched_size() {
  for (const char* k : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_STEP_NUM_TASKS"})
    if (const char* v = std::getenv(k)) return std::atoi(v);
  return 1;
}

// Open MPI's ranks open a TCP listener on every interface (its tcp BTL) unless told otherwise. A
// job whose ranks all run on this node needs none of it - they talk through shared memory - so
// unless the user chose the transports (OMPI_MCA_btl), such a job uses only "self,vader"
// (docs/usage.md, "MPI and the network").
void keep_single_node_jobs_off_the_network() {
  const char* world = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  if (!world || !local || std::getenv("OMPI_MCA_btl")) return;
  if (std::string(world) == local) setenv("OMPI_MCA_btl", "self,vader", 0);
}
}  // namespace

bool built_with_mpi() {
#ifdef CAPFLOW_HAVE_MPI
  return true;
#else
  return false;
#endif
}

void start(int* argc, char*** argv) {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started || launched_size() <= 1) return;
  keep_single_node_jobs_off_the_network();
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  g_comm = MPI_COMM_WORLD;
  MPI_Comm_rank(g_comm, &g_rank);
  MPI_Comm_size(g_comm, &g_size);
  g_started = true;
#else
  (void)argc;
  (void)argv;
#endif
}

void finish() {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) {
    if (g_comm != MPI_COMM_WORLD) MPI_Comm_free(&g_comm);
    MPI_Finalize();
  }
  g_comm = MPI_COMM_WORLD;
#endif
  g_started = false;
  g_rank = g_group = 0;
  g_size = g_groups = 1;
}

bool split(int group_size) {
  if (group_size < 1 || g_size % group_size != 0) return false;
#ifdef CAPFLOW_HAVE_MPI
  if (g_started && group_size < g_size) {
    const int world_rank = g_rank;
    g_group = world_rank / group_size;
    g_groups = g_size / group_size;
    MPI_Comm_split(MPI_COMM_WORLD, g_group, world_rank, &g_comm);
    MPI_Comm_rank(g_comm, &g_rank);
    MPI_Comm_size(g_comm, &g_size);
  }
#endif
  return true;
}

int group() {
  return g_group;
}
int groups() {
  return g_groups;
}

int rank() {
  return g_rank;
}
int size() {
  return g_size;
}

void broadcast(int* v) {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) MPI_Bcast(v, 1, MPI_INT, 0, g_comm);
#else
  (void)v;
#endif
}

namespace {
// The size of a container from rank 0, then its elements (the same machine type on every rank).
template <class C>
void broadcast_sized(C* c) {
  int n = static_cast<int>(c->size());
  broadcast(&n);
  c->resize(static_cast<size_t>(n));
#ifdef CAPFLOW_HAVE_MPI
  if (g_started && n > 0)
    MPI_Bcast(c->data(), n * static_cast<int>(sizeof((*c)[0])), MPI_BYTE, 0, g_comm);
#endif
}
}  // namespace

void broadcast(std::string* s) {
  broadcast_sized(s);
}
void broadcast(std::vector<double>* v) {
  broadcast_sized(v);
}
void broadcast(std::vector<int>* v) {
  broadcast_sized(v);
}

std::vector<double> gather(const std::vector<double>& mine) {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) {
    int n = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<size_t>(g_size)), offsets(static_cast<size_t>(g_size));
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, g_comm);
    std::vector<double> all;
    if (g_rank == 0) {
      int total = 0;
      for (int r = 0; r < g_size; ++r) {
        offsets[static_cast<size_t>(r)] = total;
        total += counts[static_cast<size_t>(r)];
      }
      all.resize(static_cast<size_t>(total));
    }
    MPI_Gatherv(mine.data(), n, MPI_DOUBLE, all.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                0, g_comm);
    return all;
  }
#endif
  return mine;
}

void abort_all(const std::string& why, int code) {
  std::fprintf(stderr, "capflow: rank %d%s: %s\n", g_rank,
               g_groups > 1 ? (" of group " + std::to_string(g_group)).c_str() : "", why.c_str());
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace capflow::parallel
