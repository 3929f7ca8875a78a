/// The four analyses behind the tools critical, localnu, correlate and clusterfit, from
/// plain data to a Product (tables + results): each has its header, and this one holds
/// them all for the code that uses several (io, cli, the tools). The tools only read files,
/// fill these inputs and write the product; everything here is testable without files.
/// Definitions and defaults: docs/analysis.md.
#pragma once

#include "cdpile/analysis/clusterfit.hpp"
#include "cdpile/analysis/correlate.hpp"
#include "cdpile/analysis/critical_study.hpp"
#include "cdpile/analysis/localnu_study.hpp"
#include "cdpile/analysis/run_record.hpp"
