// Tests of joint files: what is written reads back to the same doubles, and a damaged file is
// refused with its line and the key.
#include <gtest/gtest.h>

#include "support/joint_data.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/joint_file.hpp"

using namespace toolpoint;
using namespace toolpoint::test;

namespace {

JointFile sample_file() {
  JointFile f;
  f.interface = JointInterface::HolderTool;
  f.parameters = seed_table1_joint();
  f.parameters.c_yf = 54.123456789012345;  // not representable in few digits: round trip must keep every bit
  JointUncertainty u;
  u.confidence = 0.95;
  for (std::size_t k = 0; k < 8; ++k) {
    u.lower[k] = 0.99 * f.parameters[static_cast<int>(k)];
    u.upper[k] = 1.01 * f.parameters[static_cast<int>(k)];
    u.determined[k] = k != 1;
  }
  Eigen::Matrix<double, 8, 8> a = Eigen::Matrix<double, 8, 8>::Random();
  u.covariance = a * a.transpose() * 1e-3;
  f.uncertainty = u;
  f.identification = {{"method", "band fit \"output error\""}, {"band_hz", "10–5000"}};
  return f;
}

std::string message_of(const std::string& text) {
  try {
    parse_joint_file(text, "kht.toml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace

TEST(JointFile, RoundTripKeepsEveryBit) {
  const JointFile f = sample_file();
  const JointFile g = parse_joint_file(format_joint_file(f), "kht.toml");
  EXPECT_EQ(g.interface, f.interface);
  for (int k = 0; k < 8; ++k) EXPECT_EQ(g.parameters[k], f.parameters[k]) << JointParameters::name(k);
  ASSERT_TRUE(g.uncertainty);
  EXPECT_EQ(g.uncertainty->covariance, f.uncertainty->covariance);
  EXPECT_EQ(g.uncertainty->lower, f.uncertainty->lower);
  EXPECT_EQ(g.uncertainty->determined, f.uncertainty->determined);
  auto sorted = [](auto v) {
    std::sort(v.begin(), v.end());
    return v;
  };
  EXPECT_EQ(sorted(g.identification), sorted(f.identification));  // a TOML table has no order
  // In an assembly it replaces the joint at its interface, and only that.
  const Assembly a = example_assembly();
  const Assembly b = with_joint(a, g);
  EXPECT_EQ(b.holder_tool.parameters.c_yf, f.parameters.c_yf);
  EXPECT_EQ(b.spindle_holder.parameters.k_yf, a.spindle_holder.parameters.k_yf);
}

TEST(JointFile, SixValuesAreAReciprocalJoint) {
  const JointFile f = parse_joint_file(
      "[joint]\ninterface = \"spindle_holder\"\nk_yf = 6e8\nc_yf = 600\nk_ym = 1e5\nc_ym = 1\nk_tm = 3e6\nc_tm = 30\n",
      "ksh.toml");
  EXPECT_EQ(f.interface, JointInterface::SpindleHolder);
  EXPECT_EQ(f.parameters.k_tf, 1e5);
  EXPECT_EQ(f.parameters.c_tf, 1.0);
  EXPECT_FALSE(f.uncertainty);
}

TEST(JointFile, DamagedFilesNameTheLineAndKey) {
  const std::string head =
      "[joint]\ninterface = \"holder_tool\"\nk_yf = 4.19e7\nc_yf = 54\nk_ym = 2.06e6\nc_ym = 22.2\nk_tm = 6.5e4\nc_tm = 1\n";
  EXPECT_NE(message_of(head + "c_tmm = 3\n").find("kht.toml:9"), std::string::npos);
  EXPECT_NE(message_of(head + "c_tmm = 3\n").find("unknown key 'joint.c_tmm'"), std::string::npos);
  EXPECT_NE(message_of("[joint]\ninterface = \"holder_tool\"\nk_yf = 4.19e7\n").find("missing key joint.c_yf"),
            std::string::npos);
  EXPECT_NE(message_of("[joint]\ninterface = \"tool\"\n").find("holder_tool"), std::string::npos);
  EXPECT_NE(message_of(head + "k_tf = \"2e6\"\n").find("number"), std::string::npos);
  EXPECT_NE(message_of("[joint\n").find("kht.toml:1"), std::string::npos);
  const std::string cov =
      "\n[uncertainty]\ncovariance = [[1,0,0,0,0,0,0,0],[0,1,0,0,0,0,0,0],[0,0,1,0,0,0,0,0],[0,0,0,1,0,0,0,0],"
      "[0,0,0,0,1,0,0,0],[0,0,0,0,0,1,0,0],[0,0,0,0,0,0,1,0],[0,0,0,0,0,0,0,X]]\n";
  auto with = [&](const std::string& x) { return std::string(cov).replace(cov.find('X'), 1, x); };
  EXPECT_EQ(message_of(head + with("1")), "no error");
  EXPECT_NE(message_of(head + with("-1")).find("negative variance"), std::string::npos);
  std::string asym = with("1");
  asym.replace(asym.find("[0,1,0,0"), 8, "[5,1,0,0");
  EXPECT_NE(message_of(head + asym).find("not symmetric"), std::string::npos);
  std::string indefinite = with("1");
  indefinite.replace(indefinite.find("[1,0,0,0"), 8, "[1,2,0,0");
  indefinite.replace(indefinite.find("[0,1,0,0"), 8, "[2,1,0,0");
  EXPECT_NE(message_of(head + indefinite).find("not positive semidefinite"), std::string::npos);
  EXPECT_NE(message_of(head + "\n[uncertainty]\nlower = [1, 2]\n").find("list of 8"), std::string::npos);
  EXPECT_THROW(load_joint_file("/nonexistent/kht.toml"), IoError);
}
