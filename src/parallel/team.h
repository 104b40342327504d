// capflow/parallel/team: the processes of one capflow run. Under an MPI launcher with N > 1 ranks
// (mpirun -np N, srun) and a build with MPI (CAPFLOW_MPI), start() initialises MPI and every call
// below is a collective over the team's communicator (MPI_COMM_WORLD, or this rank's group after
// split()), made from the main thread only (MPI_THREAD_FUNNELED).
// Otherwise this is a team of one: rank 0, size 1, the collectives do nothing.
// A failed MPI call aborts every rank (MPI's default error handler).
#pragma once

#include <string>
#include <vector>

namespace capflow::parallel {

void start(int* argc, char*** argv);
void finish();  // MPI_Finalize if start() initialised MPI
// This process's rank in the team and the team's size (the world, or this rank's group after
// split).
int rank();
int size();

// Splits the world into groups of group_size consecutive ranks (ranks g * group_size ..
// (g + 1) * group_size - 1 form group g), each then a team of its own: rank(), size(), the
// broadcasts and gathers below are the group's. False (nothing changed) unless group_size
// divides size(). Call once, after start(). A sweep's cases run side by side, one per group.
bool split(int group_size);
int group();   // this rank's group (0 before a split)
int groups();  // the number of groups (1 before a split)
bool built_with_mpi();

// From rank 0 to every rank (the others' values are replaced).
void broadcast(int* v);
void broadcast(std::string* s);
void broadcast(std::vector<double>* v);
void broadcast(std::vector<int>* v);

// Every rank's block to rank 0, concatenated in rank order (the others get an empty vector).
std::vector<double> gather(const std::vector<double>& mine);

// Ends every rank of the world with `code` after printing why (from any rank).
[[noreturn]] void abort_all(const std::string& why, int code);

}  // namespace capflow::parallel
