// Pinocchio C++ timing baseline for the Franka Panda arm (7 dof).
//
// Model: mechanisms/urdf/panda.urdf loaded with pinocchio::urdf::buildModel
// (mimic tags ignored -> 9 dof), then buildReducedModel locking
// panda_finger_joint1/2 at q = 0 (pinocchio::neutral) -> 7 dof, the same model
// as benches/baselines/pinocchio/panda_fixture.py / tests/fixtures/panda_pinocchio.json.
// Gravity: Pinocchio default (0, 0, -9.81).
//
// Usage:
//   panda_bench [URDF]            timing run, JSON on stdout, info on stderr
//   panda_bench --verify [URDF]   reads lines "q(7) qd(7) qdd(7) tau_in(7)" on
//                                 stdin, prints M, nle, g, tau, aba, J (JSON
//                                 lines) for a cross-check against the fixture.
//
// Timing: 1000 random states (std::mt19937_64, fixed seed), 11 interleaved
// rounds; each round runs every routine once over all 1000 states and records
// the mean ns per call (std::chrono::steady_clock around the 1000-call loop).
// Reported per routine: median and min over the 11 rounds (after one
// unrecorded warm-up round). Results flow into a volatile sink; an empty asm
// memory clobber after every call keeps calls from being merged or hoisted.

#include <pinocchio/parsers/urdf.hpp>

#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/model.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#ifndef PANDA_URDF_DEFAULT
#define PANDA_URDF_DEFAULT "mechanisms/urdf/panda.urdf"
#endif

using pinocchio::Data;
using pinocchio::Model;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {

volatile double g_sink = 0.0;

inline void clobber() { asm volatile("" : : : "memory"); }

Model build_panda(const std::string & urdf)
{
  Model full;
  pinocchio::urdf::buildModel(urdf, full); // verbose = false, mimic = false
  if (full.nq != 9 || full.nv != 9)
  {
    std::fprintf(stderr, "unexpected full model nq=%d nv=%d\n", full.nq, full.nv);
    std::exit(2);
  }
  std::vector<pinocchio::JointIndex> lock = {
    full.getJointId("panda_finger_joint1"), full.getJointId("panda_finger_joint2")};
  VectorXd q_ref = pinocchio::neutral(full);
  for (auto j : lock)
  {
    if (j >= (pinocchio::JointIndex)full.njoints || q_ref[full.joints[j].idx_q()] != 0.0)
    {
      std::fprintf(stderr, "finger joint missing or not locked at 0\n");
      std::exit(2);
    }
  }
  Model reduced = pinocchio::buildReducedModel(full, lock, q_ref);
  if (reduced.nq != 7 || reduced.nv != 7)
  {
    std::fprintf(stderr, "unexpected reduced model nq=%d\n", reduced.nq);
    std::exit(2);
  }
  for (int i = 1; i <= 7; ++i)
  {
    if (reduced.names[i] != "panda_joint" + std::to_string(i))
    {
      std::fprintf(stderr, "unexpected joint %s\n", reduced.names[i].c_str());
      std::exit(2);
    }
  }
  return reduced;
}

void print_vec(const VectorXd & v)
{
  std::printf("[");
  for (Eigen::Index i = 0; i < v.size(); ++i)
    std::printf("%s%.17g", i ? ", " : "", v[i]);
  std::printf("]");
}

void print_mat(const MatrixXd & m)
{
  std::printf("[");
  for (Eigen::Index r = 0; r < m.rows(); ++r)
  {
    std::printf("%s", r ? ", " : "");
    print_vec(m.row(r).transpose());
  }
  std::printf("]");
}

int verify(const Model & model, pinocchio::FrameIndex hand)
{
  Data data(model);
  VectorXd q(7), qd(7), qdd(7), tau_in(7);
  while (true)
  {
    for (VectorXd * v : {&q, &qd, &qdd, &tau_in})
      for (int i = 0; i < 7; ++i)
        if (!(std::cin >> (*v)[i]))
          return 0;
    MatrixXd M = pinocchio::crba(model, data, q);
    M.triangularView<Eigen::StrictlyLower>() = M.transpose().triangularView<Eigen::StrictlyLower>();
    VectorXd nle = pinocchio::nonLinearEffects(model, data, q, qd);
    VectorXd g = pinocchio::computeGeneralizedGravity(model, data, q);
    VectorXd tau = pinocchio::rnea(model, data, q, qd, qdd);
    VectorXd ddq = pinocchio::aba(model, data, q, qd, tau_in);
    pinocchio::Data::Matrix6x J(6, 7);
    J.setZero();
    pinocchio::computeFrameJacobian(model, data, q, hand, pinocchio::LOCAL_WORLD_ALIGNED, J);
    std::printf("{\"M\": ");
    print_mat(M);
    std::printf(", \"nle\": ");
    print_vec(nle);
    std::printf(", \"g\": ");
    print_vec(g);
    std::printf(", \"tau\": ");
    print_vec(tau);
    std::printf(", \"aba\": ");
    print_vec(ddq);
    std::printf(", \"J\": ");
    print_mat(J);
    std::printf("}\n");
  }
}

// Mean ns per call of f(k) over k = 0..n-1 (one steady_clock pair around the loop).
template<typename F>
double time_loop(F & f, std::size_t n)
{
  double acc = 0.0;
  clobber();
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < n; ++k)
  {
    acc += f(k);
    clobber();
  }
  const auto t1 = std::chrono::steady_clock::now();
  g_sink = g_sink + acc;
  return std::chrono::duration<double, std::nano>(t1 - t0).count() / double(n);
}

} // namespace

int main(int argc, char ** argv)
{
  bool verify_mode = false;
  std::string urdf = PANDA_URDF_DEFAULT;
  for (int i = 1; i < argc; ++i)
  {
    if (std::strcmp(argv[i], "--verify") == 0)
      verify_mode = true;
    else
      urdf = argv[i];
  }

  const Model model = build_panda(urdf);
  const pinocchio::FrameIndex hand = model.getFrameId("panda_hand", pinocchio::BODY);
  if (hand >= (pinocchio::FrameIndex)model.nframes)
  {
    std::fprintf(stderr, "no panda_hand frame\n");
    return 2;
  }
  if (verify_mode)
    return verify(model, hand);

  std::fprintf(stderr, "model: nq=%d nv=%d njoints=%d nframes=%d hand frame id=%zu\n", model.nq,
               model.nv, model.njoints, model.nframes, (std::size_t)hand);

  // ---- random states (fixed seed) ------------------------------------------
  constexpr std::size_t N = 1000;
  constexpr int ROUNDS = 11;
  std::mt19937_64 rng(20261126ULL);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<VectorXd> Q(N), V(N), A(N), T(N);
  for (std::size_t k = 0; k < N; ++k)
  {
    Q[k].resize(7);
    V[k].resize(7);
    A[k].resize(7);
    T[k].resize(7);
    for (int i = 0; i < 7; ++i)
    {
      const double lo = model.lowerPositionLimit[i], hi = model.upperPositionLimit[i];
      Q[k][i] = lo + (hi - lo) * u01(rng);
      V[k][i] = -2.0 + 4.0 * u01(rng);
      A[k][i] = -5.0 + 10.0 * u01(rng);
      T[k][i] = -20.0 + 40.0 * u01(rng);
    }
  }

  Data data(model);
  pinocchio::Data::Matrix6x J(6, model.nv);
  J.setZero();

  using pinocchio::LOCAL_WORLD_ALIGNED;
  using pinocchio::Convention;
  // Each routine is a lambda (inlined into time_loop, no std::function).
  auto crba = [&](std::size_t k) {
    pinocchio::crba(model, data, Q[k]); // default convention (LOCAL); upper triangle of data.M
    return data.M(0, 6) + data.M(6, 6);
  };
  auto crba_world = [&](std::size_t k) {
    pinocchio::crba(model, data, Q[k], Convention::WORLD);
    return data.M(0, 6) + data.M(6, 6);
  };
  auto nle = [&](std::size_t k) {
    pinocchio::nonLinearEffects(model, data, Q[k], V[k]);
    return data.nle[0] + data.nle[6];
  };
  auto crba_nle = [&](std::size_t k) {
    pinocchio::crba(model, data, Q[k]);
    pinocchio::nonLinearEffects(model, data, Q[k], V[k]);
    return data.M(0, 6) + data.nle[6];
  };
  auto rnea = [&](std::size_t k) {
    pinocchio::rnea(model, data, Q[k], V[k], A[k]);
    return data.tau[0] + data.tau[6];
  };
  auto aba = [&](std::size_t k) {
    pinocchio::aba(model, data, Q[k], V[k], T[k]); // default convention (LOCAL)
    return data.ddq[0] + data.ddq[6];
  };
  auto aba_world = [&](std::size_t k) {
    pinocchio::aba(model, data, Q[k], V[k], T[k], Convention::WORLD);
    return data.ddq[0] + data.ddq[6];
  };
  auto gravity = [&](std::size_t k) {
    pinocchio::computeGeneralizedGravity(model, data, Q[k]);
    return data.g[0] + data.g[6];
  };
  auto jac = [&](std::size_t k) {
    // self-contained: computes the placements of the supporting joints itself
    pinocchio::computeFrameJacobian(model, data, Q[k], hand, LOCAL_WORLD_ALIGNED, J);
    return J(0, 0) + J(5, 6);
  };
  auto fk_jac = [&](std::size_t k) {
    pinocchio::forwardKinematics(model, data, Q[k]);
    pinocchio::computeFrameJacobian(model, data, Q[k], hand, LOCAL_WORLD_ALIGNED, J);
    return J(0, 0) + J(5, 6);
  };

  const char * names[] = {"crba",
                          "crba_world_convention",
                          "nonLinearEffects",
                          "crba+nonLinearEffects",
                          "rnea",
                          "aba",
                          "aba_world_convention",
                          "computeGeneralizedGravity",
                          "computeFrameJacobian_hand",
                          "forwardKinematics+computeFrameJacobian_hand"};
  constexpr std::size_t NR = sizeof(names) / sizeof(names[0]);
  std::vector<std::vector<double>> per_round(NR);
  auto run_all = [&](bool record) {
    double r[NR] = {time_loop(crba, N),    time_loop(crba_world, N), time_loop(nle, N),
                    time_loop(crba_nle, N), time_loop(rnea, N),      time_loop(aba, N),
                    time_loop(aba_world, N), time_loop(gravity, N),  time_loop(jac, N),
                    time_loop(fk_jac, N)};
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
