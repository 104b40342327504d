#include "parallel/team.h"

#include <cstdio>
#include <cstdlib>

#ifdef CAPFLOW_HAVE_MPI
#include <mpi.h>
#endif

namespace capflow::parallel {

namespace {
bool g_started = false;
int g_rank = 0, g_size = 1;

// The launcher's rank count, from its environment (Open MPI, MPICH/PMI): 1 when not launched.
int launched_size() {
  for (const char* k : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(k)) return std::atoi(v);
  return 1;
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
  int provided = 0;
  MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
  MPI_Comm_size(MPI_COMM_WORLD, &g_size);
  g_started = true;
#else
  (void)argc;
  (void)argv;
#endif
}

void finish() {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) MPI_Finalize();
#endif
  g_started = false;
}

int rank() {
  return g_rank;
}
int size() {
  return g_size;
}

void broadcast(int* v) {
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) MPI_Bcast(v, 1, MPI_INT, 0, MPI_COMM_WORLD);
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
    MPI_Bcast(c->data(), n * static_cast<int>(sizeof((*c)[0])), MPI_BYTE, 0, MPI_COMM_WORLD);
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
    MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
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
                0, MPI_COMM_WORLD);
    return all;
  }
#endif
  return mine;
}

void abort_all(const std::string& why, int code) {
  std::fprintf(stderr, "capflow: rank %d: %s\n", g_rank, why.c_str());
#ifdef CAPFLOW_HAVE_MPI
  if (g_started) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace capflow::parallel
