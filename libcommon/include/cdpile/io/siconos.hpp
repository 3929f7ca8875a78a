/// Siconos' text format of 2D frictional contact problems in Delassus form
/// (cd/delassus.hpp), both ways: Siconos' own test problems come in through it
/// (numerics/src/FrictionContact/test/data/fc2d_granularflowonwall_*.dat in the Siconos
/// repository), and the engine's steps go out through it to other solvers
/// (docs/method.md, "Delassus problems from other codes"). The engine knows no files:
/// this is io's.
#pragma once

#include "cdpile/cd/delassus.hpp"

#include <ostream>
#include <string>

namespace cdpile::io {

/// Reads a problem in the text format of Siconos' `frictionContact_printInFile` (2D):
/// dimension, number of contacts, the matrix (storage code 2 = sparse, a CSparse
/// `cs_print` listing in compressed columns), q, mu. Throws cdpile::Error naming the
/// file and the line on any malformed or inconsistent content: a truncated file, counts
/// that disagree (matrix size against 2m, entries against the listed locations and nnz,
/// 3m values for q and mu), a column out of sequence, a duplicate entry, a token that is
/// not a finite number, a negative mu, or anything after mu.
cd::DelassusProblem read_siconos_fc2d(const std::string& path);

/// Writes `p` in the format read_siconos_fc2d reads, which is Siconos' own (its reader
/// `frictionContact_new_from_filename` takes it): storage code 2, W as a CSparse
/// `cs_print` listing in compressed columns, then q and mu on one line each. Values are
/// written with 17 significant digits, so a problem read back is the same bit for bit.
/// Throws cdpile::Error if the stream fails.
void write_siconos_fc2d(std::ostream& out, const cd::DelassusProblem& p);

}  // namespace cdpile::io
