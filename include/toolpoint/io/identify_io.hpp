// toolpoint: identification results as tables — the I/O layer of identify.hpp (written as CSV
// by write_table_csv, io.hpp).
//
// Units (in the column names): SI — k_yf N/m, c_yf N·s/m, …, as joint.hpp; frequency in Hz.
#pragma once

#include "toolpoint/identify/identify.hpp"
#include "toolpoint/io/io.hpp"

namespace toolpoint {

// K(ω) as a table: frequency_hz, the eight parameters (units in the column names) and the
// condition numbers and noise gains per frequency.
Table joint_table(const JointSeries& series);

}  // namespace toolpoint
