// toolpoint: identification results as tables (identify_io.hpp). Units: SI, frequency in Hz.
#include "toolpoint/io/identify_io.hpp"

namespace toolpoint {

Table joint_table(const JointSeries& js) {
  Table t;
  t.columns = {"frequency_hz",       "k_yf_N_per_m",       "c_yf_N_s_per_m",   "k_ym_N",
               "c_ym_N_s",           "k_tf_N_per_rad",     "c_tf_N_s_per_rad", "k_tm_N_m_per_rad",
               "c_tm_N_m_s_per_rad", "cond_A11_minus_G11", "cond_K_inverse",   "gain_k_yf",
               "gain_c_yf",          "gain_k_ym",          "gain_c_ym",        "gain_k_tf",
               "gain_c_tf",          "gain_k_tm",          "gain_c_tm"};
  for (std::size_t i = 0; i < js.size(); ++i) {
    std::vector<double> row{js.frequency_hz[i]};
    for (int k = 0; k < 8; ++k) row.push_back(js.parameters[i][k]);
    row.push_back(js.estimates[i].cond_difference);
    row.push_back(js.estimates[i].cond_flexibility);
    for (double gk : js.estimates[i].noise_gain) row.push_back(gk);
    t.rows.push_back(std::move(row));
  }
  return t;
}

}  // namespace toolpoint
