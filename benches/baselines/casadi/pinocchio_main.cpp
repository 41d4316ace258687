// Pinocchio 4.1's C++ routines on the CasADi baseline's robots, timed and checked like
// CasADi's C (casadi_main.c) and our code (ours.rs), built by casadi_bench.py against the
// headers of the pip packages (`pin`, `cmeel-eigen`, `cmeel-urdfdom-headers`; the flags of
// benches/baselines/pinocchio/build.sh, -O3 -march=native):
//
//   pinocchio_main URDF [LOCK..] -- check STATES S         every routine at each state
//   pinocchio_main URDF [LOCK..] -- time ROUTINE STATES S BATCHES CALLS
//                                                            ns of thread CPU per call, per batch
//
// The model: the URDF (mimic tags ignored), the joints LOCK fixed at 0 (buildReducedModel at
// pinocchio::neutral), as pinocchio_reference.py builds it. STATES: S states of 4 n doubles
// (q, v, a, tau in Pinocchio's joint order), native byte order. Routines, as CasADi's
// functions are named: crba (M, its upper triangle mirrored), bias (nonLinearEffects,
// C q' + g), mass_bias (crba then nonLinearEffects), rnea (tau), aba (q''). The Data is
// allocated once, before timing; outputs are read from it (no copies timed).

#include <pinocchio/parsers/urdf.hpp>

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

using pinocchio::Data;
using pinocchio::Model;
using Eigen::VectorXd;

namespace {

double now_ns()
{
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e9 * double(t.tv_sec) + double(t.tv_nsec);
}

Model build(const std::string & urdf, const std::vector<std::string> & lock)
{
  Model full;
  pinocchio::urdf::buildModel(urdf, full);
  if (lock.empty())
    return full;
  std::vector<pinocchio::JointIndex> ids;
  for (const auto & j : lock)
    ids.push_back(full.getJointId(j));
  return pinocchio::buildReducedModel(full, ids, pinocchio::neutral(full));
}

std::vector<double> read_states(const char * path, long count, int n)
{
  std::vector<double> x(size_t(4 * n * count));
  FILE * f = std::fopen(path, "rb");
  if (!f || std::fread(x.data(), sizeof(double), x.size(), f) != x.size())
  {
    std::fprintf(stderr, "cannot read %ld states from %s\n", count, path);
    std::exit(1);
  }
  std::fclose(f);
  return x;
}

const char * const ROUTINES[] = {"crba", "bias", "mass_bias", "rnea", "aba"};

// Routine r at state s (q, v, a, tau mapped onto the state's doubles); its first output
// entry, so that the call cannot be dropped.
double call(int r, const Model & m, Data & d, const double * s)
{
  const int n = m.nv;
  Eigen::Map<const VectorXd> q(s, n), v(s + n, n), a(s + 2 * n, n), tau(s + 3 * n, n);
  switch (r)
  {
  case 0:
    pinocchio::crba(m, d, q);
    return d.M(0, 0);
  case 1:
    pinocchio::nonLinearEffects(m, d, q, v);
    return d.nle[0];
  case 2:
    pinocchio::crba(m, d, q);
    pinocchio::nonLinearEffects(m, d, q, v);
    return d.M(0, 0) + d.nle[0];
  case 3:
    pinocchio::rnea(m, d, q, v, a);
    return d.tau[0];
  default:
    pinocchio::aba(m, d, q, v, tau);
    return d.ddq[0];
  }
}

void print_vector(const VectorXd & v)
{
  for (Eigen::Index i = 0; i < v.size(); ++i)
    std::printf(" %.17g", v[i]);
}

void print_mass(Data & d)
{
  d.M.triangularView<Eigen::StrictlyLower>() = d.M.transpose().triangularView<Eigen::StrictlyLower>();
  for (Eigen::Index i = 0; i < d.M.rows(); ++i)
    print_vector(VectorXd(d.M.row(i).transpose()));
}

} // namespace

int main(int argc, char ** argv)
{
  int sep = 1;
  while (sep < argc && std::strcmp(argv[sep], "--") != 0)
    ++sep;
  if (sep < 2 || sep + 1 >= argc)
  {
    std::fprintf(stderr, "usage: %s URDF [LOCK..] -- check STATES S | time ROUTINE STATES S BATCHES CALLS\n",
                 argv[0]);
    return 2;
  }
  const Model m = build(argv[1], std::vector<std::string>(argv + 2, argv + sep));
  Data d(m);
  const int n = m.nv;
  char ** rest = argv + sep + 1;
  const int left = argc - sep - 1;
  if (left >= 3 && std::strcmp(rest[0], "check") == 0)
  {
    const long count = std::atol(rest[2]);
    const std::vector<double> x = read_states(rest[1], count, n);
    for (int r = 0; r < 5; ++r)
      for (long s = 0; s < count; ++s)
      {
        call(r, m, d, x.data() + 4 * n * s);
        std::printf("%s %ld", ROUTINES[r], s);
        if (r == 0 || r == 2)
          print_mass(d);
        if (r == 1 || r == 2)
          print_vector(d.nle);
        if (r == 3)
          print_vector(d.tau);
        if (r == 4)
          print_vector(d.ddq);
        std::printf("\n");
      }
    return 0;
  }
  if (left >= 6 && std::strcmp(rest[0], "time") == 0)
  {
    int r = -1;
    for (int k = 0; k < 5; ++k)
      if (std::strcmp(ROUTINES[k], rest[1]) == 0)
        r = k;
    if (r < 0)
    {
      std::fprintf(stderr, "no routine %s\n", rest[1]);
      return 2;
    }
    const long count = std::atol(rest[3]), batches = std::atol(rest[4]), calls = std::atol(rest[5]);
    const std::vector<double> x = read_states(rest[2], count, n);
    volatile double sink = 0;
    for (long b = -1; b < batches; ++b) // batch -1: warm-up
    {
      const double t0 = now_ns();
      for (long i = 0; i < calls; ++i)
        sink = sink + call(r, m, d, x.data() + 4 * n * (i % count));
      const double t1 = now_ns();
      if (b >= 0)
        std::printf("%.2f\n", (t1 - t0) / double(calls));
    }
    return 0;
  }
  std::fprintf(stderr, "unknown mode %s\n", rest[0]);
  return 2;
}
