/// The keys of the run parameters that the layers below sim read from a file
/// (/parameters of a pile or run, docs/schema.md), each spelled once: the friction and the
/// critical test's eps, by which io and analysis compare a run's recorded rule with the one
/// asked for, and gravity, by which they scale speeds and energies. sim::run_parameters()
/// declares these rows with these constants; every other key is spelled in its row alone
/// (sim::parameter_key reads it back for sim and the tools), so a new parameter is its
/// field and its row, and comes here only if io or analysis must read it. A key carries its
/// unit, so it changes only with the schema's version: these are the files' words.
#pragma once

namespace cdpile::keys {

inline constexpr char critical_eps[] = "critical_eps";
inline constexpr char mu_grain[] = "mu_grain";
inline constexpr char mu_wall[] = "mu_wall";
inline constexpr char gravity_m_s2[] = "gravity_m_s2";

}  // namespace cdpile::keys
