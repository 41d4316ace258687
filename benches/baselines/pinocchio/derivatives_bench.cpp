// Pinocchio C++ timing baseline for the derivatives of the dynamics: computeRNEADerivatives
// (dtau/dq, dtau/dv, and M as dtau/da) and computeABADerivatives (ddq/dq, ddq/dv, M^-1),
// beside rnea and aba, on the Franka Panda (7 dof), the UR5 (6 dof) and Solo12 (12 dof,
// fixed base).
//
// Models (the same as benches/baselines/pinocchio/derivatives_fixture.py and the
// tests' fixtures tests/fixtures/*_derivatives.json):
//   panda   mechanisms/urdf/panda.urdf, pinocchio::urdf::buildModel (mimic ignored -> 9 dof),
//           then buildReducedModel locking panda_finger_joint1/2 at q = 0 -> 7 dof;
//   ur5     mechanisms/urdf/ur5_robot.urdf, buildModel -> 6 dof;
//   solo12  mechanisms/urdf/solo12.urdf, buildModel without a root joint (the base fixed to
//           the world, as `mechanism import` writes it) -> 12 dof.
// Gravity: Pinocchio's default (0, 0, -9.81).
//
// Usage:
//   derivatives_bench ROBOT URDF     ROBOT one of panda, ur5, solo12; JSON on stdout
//
// Timing: 1000 random states (std::mt19937_64, seed 20261126): q uniform inside the joint
// limits clipped to [-pi, pi], v in (-2, 2), a in (-5, 5), tau in (-20, 20); 11
// interleaved rounds after one unrecorded warm-up round, each round timing every routine
// over all 1000 states (one pair of this thread's CPU clock, CLOCK_THREAD_CPUTIME_ID, around
// the loop, as our harness) and recording the mean ns per call. Reported per routine: the median and the min over the rounds.
// Results flow into a volatile sink; an empty asm memory clobber after every call keeps
// calls from being merged or hoisted. One pinocchio::Data is reused for all calls.

#include <pinocchio/parsers/urdf.hpp>

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

using pinocchio::Data;
using pinocchio::Model;
using Eigen::VectorXd;

namespace {

volatile double g_sink = 0.0;

inline void clobber() { asm volatile("" : : : "memory"); }

[[noreturn]] void fail(const char * what)
{
  std::fprintf(stderr, "%s\n", what);
  std::exit(2);
}

Model build(const std::string & robot, const std::string & urdf)
{
  Model full;
  pinocchio::urdf::buildModel(urdf, full); // verbose = false, mimic = false
  if (robot == "panda")
  {
    std::vector<pinocchio::JointIndex> lock = {
      full.getJointId("panda_finger_joint1"), full.getJointId("panda_finger_joint2")};
    VectorXd q_ref = pinocchio::neutral(full);
    for (auto j : lock)
      if (j >= (pinocchio::JointIndex)full.njoints || q_ref[full.joints[j].idx_q()] != 0.0)
        fail("finger joint missing or not locked at 0");
    Model reduced = pinocchio::buildReducedModel(full, lock, q_ref);
    if (reduced.nv != 7)
      fail("unexpected reduced Panda");
    return reduced;
  }
  if (robot == "ur5" && full.nv == 6)
    return full;
  if (robot == "solo12" && full.nv == 12)
    return full;
  fail("unknown robot or unexpected model size");
}

// Mean ns of thread CPU time per call of f(k) over k = 0..n-1 (one clock pair around the loop).
template<typename F>
double time_loop(F & f, std::size_t n)
{
  double acc = 0.0;
  clobber();
  timespec t0, t1;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
  for (std::size_t k = 0; k < n; ++k)
  {
    acc += f(k);
    clobber();
  }
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t1);
  g_sink = g_sink + acc;
  const double ns = 1e9 * double(t1.tv_sec - t0.tv_sec) + double(t1.tv_nsec - t0.tv_nsec);
  return ns / double(n);
}

} // namespace

int main(int argc, char ** argv)
{
  if (argc != 3)
    fail("usage: derivatives_bench panda|ur5|solo12 URDF");
  const Model model = build(argv[1], argv[2]);
  const int nv = model.nv;
  std::fprintf(stderr, "model %s: nq=%d nv=%d\n", argv[1], model.nq, nv);

  constexpr std::size_t N = 1000;
  constexpr int ROUNDS = 11;
  std::mt19937_64 rng(20261126ULL);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<VectorXd> Q(N), V(N), A(N), T(N);
  for (std::size_t k = 0; k < N; ++k)
  {
    Q[k].resize(nv);
    V[k].resize(nv);
    A[k].resize(nv);
    T[k].resize(nv);
    for (int i = 0; i < nv; ++i)
    {
      const double lo = std::max(model.lowerPositionLimit[i], -M_PI);
      const double hi = std::min(model.upperPositionLimit[i], M_PI);
      Q[k][i] = lo + (hi - lo) * u01(rng);
      V[k][i] = -2.0 + 4.0 * u01(rng);
      A[k][i] = -5.0 + 10.0 * u01(rng);
      T[k][i] = -20.0 + 40.0 * u01(rng);
    }
  }

  Data data(model);
  const int last = nv - 1;
  auto rnea = [&](std::size_t k) {
    pinocchio::rnea(model, data, Q[k], V[k], A[k]);
    return data.tau[0] + data.tau[last];
  };
  auto aba = [&](std::size_t k) {
    pinocchio::aba(model, data, Q[k], V[k], T[k]);
    return data.ddq[0] + data.ddq[last];
  };
  auto rnea_derivatives = [&](std::size_t k) {
    pinocchio::computeRNEADerivatives(model, data, Q[k], V[k], A[k]);
    return data.dtau_dq(0, last) + data.dtau_dv(last, 0);
  };
  auto aba_derivatives = [&](std::size_t k) {
    pinocchio::computeABADerivatives(model, data, Q[k], V[k], T[k]);
    return data.ddq_dq(0, last) + data.ddq_dv(last, 0) + data.Minv(0, last);
  };

  const char * names[] = {"rnea", "aba", "computeRNEADerivatives", "computeABADerivatives"};
  constexpr std::size_t NR = sizeof(names) / sizeof(names[0]);
  std::vector<std::vector<double>> per_round(NR);
  auto run_all = [&](bool record) {
    double r[NR] = {time_loop(rnea, N), time_loop(aba, N), time_loop(rnea_derivatives, N),
                    time_loop(aba_derivatives, N)};
    if (record)
      for (std::size_t i = 0; i < NR; ++i)
        per_round[i].push_back(r[i]);
  };

  run_all(false); // warm-up round, not recorded
  for (int round = 0; round < ROUNDS; ++round)
    run_all(true);

  std::printf("{\n");
  for (std::size_t ri = 0; ri < NR; ++ri)
  {
    std::vector<double> v = per_round[ri];
    std::sort(v.begin(), v.end());
    std::printf("  \"%s\": {\"median_ns\": %.1f, \"min_ns\": %.1f}%s\n", names[ri],
                v[v.size() / 2], v.front(), ri + 1 < NR ? "," : "");
  }
  std::printf("}\n");
  std::fprintf(stderr, "sink=%g (ignore)\n", (double)g_sink);
  return 0;
}
