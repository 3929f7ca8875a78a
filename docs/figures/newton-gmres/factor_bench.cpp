// The cost of the newton solver's sparse LU on one J (docs/performance.md, "The newton
// solver", "GMRES with the step's factor"): KLU with its AMD ordering, COLAMD and METIS
// (through CHOLMOD), its refactorisation, UMFPACK without iterative refinement, Eigen's
// SparseLU, and CHOLMOD's supernodal Cholesky on the symmetrised J made positive (the
// pattern's cost only). Not part of the build; see README.md for the matrix.
//   g++ -O2 -march=native -DNDEBUG -I/usr/include/eigen3 -I/usr/include/suitesparse \
//     factor_bench.cpp -o factor_bench -lklu -lumfpack -lcholmod -lamd -lcolamd -lbtf \
//     -lsuitesparseconfig && ./factor_bench J.mtx
#include <Eigen/KLUSupport>
#include <Eigen/UmfPackSupport>
#include <Eigen/SparseLU>
#include <Eigen/CholmodSupport>
#include <unsupported/Eigen/SparseExtra>
#include <chrono>
#include <cstdio>
#include <cholmod.h>
using SM = Eigen::SparseMatrix<double>;
double now(){return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();}
static cholmod_common cc;
int32_t metis_order(int32_t n, int32_t* Ap, int32_t* Ai, int32_t* Perm, klu_common*) {
  // pattern of A + A^T through CHOLMOD
  cholmod_sparse* A = cholmod_allocate_sparse(n, n, Ap[n], 1, 1, 0, CHOLMOD_PATTERN, &cc);
  for (int i=0;i<=n;++i) ((int*)A->p)[i]=Ap[i];
  for (int i=0;i<Ap[n];++i) ((int*)A->i)[i]=Ai[i];
  cholmod_sparse* AT = cholmod_transpose(A, 0, &cc);
  cholmod_sparse* S = cholmod_add(A, AT, nullptr, nullptr, 0, 0, &cc);
  S->stype = 1;
  int ok = cholmod_metis(S, nullptr, 0, 1, Perm, &cc);
  cholmod_free_sparse(&A,&cc); cholmod_free_sparse(&AT,&cc); cholmod_free_sparse(&S,&cc);
  return ok;
}
int main(int argc, char** argv) {
  cholmod_start(&cc);
  SM J; Eigen::loadMarket(J, argv[1]); J.makeCompressed();
  Eigen::VectorXd b = Eigen::VectorXd::Random(J.rows()), x;
  const int reps = 20;
  for (int ord : {0, 1, 3}) {
    Eigen::KLU<SM> lu;
    lu.kluCommon().ordering = ord;
    if (ord == 3) lu.kluCommon().user_order = metis_order;
    double t0 = now(); lu.analyzePattern(J); double t1 = now(); lu.factorize(J); double t2 = now();
    for (int r=0;r<reps;++r) x = lu.solve(b);
    double t3 = now();
    double t4 = now(); for (int r=0;r<5;++r) lu.factorize(J); double t5=now();
    std::printf("KLU ord %d: analyze %.2f ms factor %.2f ms refactor(factorize) %.2f ms solve %.3f ms  res %.1e\n", ord,
      1e3*(t1-t0), 1e3*(t2-t1), 1e3*(t5-t4)/5, 1e3*(t3-t2)/reps, (J*x-b).norm()/b.norm());
  }
  for (int ord : {0, 1, 3}) {
    klu_common c; klu_defaults(&c); c.ordering = ord; c.user_order = metis_order;
    klu_symbolic* S = klu_analyze(J.rows(), J.outerIndexPtr(), J.innerIndexPtr(), &c);
    klu_numeric* N = klu_factor(J.outerIndexPtr(), J.innerIndexPtr(), J.valuePtr(), S, &c);
    double t0=now(); for (int r=0;r<5;++r) klu_refactor(J.outerIndexPtr(), J.innerIndexPtr(), J.valuePtr(), S, N, &c); double t1=now();
    std::printf("raw KLU ord %d: lnz %ld unz %ld nblocks %d refactor %.2f ms\n", ord, (long)N->lnz, (long)N->unz, S->nblocks, 1e3*(t1-t0)/5);
  }
  for (int strat : {0, 3}) {
    Eigen::UmfPackLU<SM> lu;
    lu.umfpackControl()(UMFPACK_IRSTEP) = 0;
    lu.umfpackControl()(UMFPACK_STRATEGY) = strat;
    double t0 = now(); lu.analyzePattern(J); double t1 = now(); lu.factorize(J); double t2 = now();
    for (int r=0;r<reps;++r) x = lu.solve(b);
    double t3 = now();
    std::printf("UMFPACK strat %d IRSTEP 0: analyze %.2f factor %.2f solve %.3f res %.1e\n", strat, 1e3*(t1-t0), 1e3*(t2-t1), 1e3*(t3-t2)/reps, (J*x-b).norm()/b.norm());
  }
  {
    Eigen::SparseLU<SM> lu;
    double t0 = now(); lu.analyzePattern(J); double t1 = now(); lu.factorize(J); double t2 = now();
    for (int r=0;r<reps;++r) x = lu.solve(b);
    double t3 = now();
    std::printf("SparseLU: analyze %.2f factor %.2f solve %.3f nnzL %ld nnzU %ld res %.1e\n", 1e3*(t1-t0), 1e3*(t2-t1), 1e3*(t3-t2)/reps, (long)lu.nnzL(), (long)lu.nnzU(), (J*x-b).norm()/b.norm());
  }
  {
    SM S = SM(0.5*(J + SM(J.transpose())));
    double dmax = 0; for (int k=0;k<S.rows();++k) dmax = std::max(dmax, std::abs(S.coeff(k,k)));
    for (int k=0;k<S.rows();++k) S.coeffRef(k,k) += 10*dmax;
    Eigen::CholmodSupernodalLLT<SM> ch;
    double t0 = now(); ch.analyzePattern(S); double t1 = now(); ch.factorize(S); double t2 = now();
    for (int r=0;r<reps;++r) x = ch.solve(b);
    double t3 = now();
    std::printf("CHOLMOD supernodal LLT of sym part: analyze %.2f factor %.2f solve %.3f info %d\n", 1e3*(t1-t0), 1e3*(t2-t1), 1e3*(t3-t2)/reps, (int)ch.info());
  }
}
