// The library's messages name its fields, and the front end spells them (cdpile/fields.hpp):
// another front end than the tools gets its own names in the same messages.
#include "cdpile/error.hpp"
#include "cdpile/fields.hpp"
#include "cdpile/sim/tilt.hpp"
#include "cdpile/sim/warnings.hpp"

#include <gtest/gtest.h>

using namespace cdpile;

namespace {
std::string refusal(const sim::TiltOptions& o) {
  try {
    sim::validate(o);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Fields, MessagesNameFieldsAsTheFrontEndSpellsThem) {
  sim::TiltOptions o;
  o.rate_deg = 0.0;
  set_field_spelling([](const std::string& f) { return "'" + f + "'"; });
  EXPECT_EQ(refusal(o), "'rate_deg' must be > 0");
  const auto w = sim::run_warnings(1000, 11, 0.0, 1e-3);
  ASSERT_EQ(w.size(), 1u);
  EXPECT_NE(w[0].find("(raise 'max_sweeps';"), std::string::npos) << w[0];
  set_field_spelling(nullptr);  // no front end: the long option of the field's name
  EXPECT_EQ(refusal(o), "--rate-deg must be > 0");
  EXPECT_EQ(field("max_sweeps"), "--max-sweeps");
}
