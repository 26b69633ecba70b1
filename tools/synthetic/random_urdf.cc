#include "tools/synthetic/random_urdf.h"

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>
#include <vector>

namespace igms::synthetic {
namespace {

struct Gen {
  std::mt19937 rng;
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }
  std::string vec(double a, double b, double c) {
    std::ostringstream s;
    s.precision(17);
    s << a << ' ' << b << ' ' << c;
    return s.str();
  }
  std::string origin() {
    return "<origin xyz=\"" + vec(uniform(-0.4, 0.4), uniform(-0.4, 0.4), uniform(-0.4, 0.4)) + "\" rpy=\"" +
           vec(uniform(-M_PI, M_PI), uniform(-1.5, 1.5), uniform(-M_PI, M_PI)) + "\"/>";
  }
  std::string axis(double p_aligned) {
    if (chance(p_aligned)) {
      const int k = static_cast<int>(uniform(0.0, 3.0)) % 3;
      const double s = chance(0.5) ? 1.0 : -1.0;
      return "<axis xyz=\"" + vec(k == 0 ? s : 0.0, k == 1 ? s : 0.0, k == 2 ? s : 0.0) + "\"/>";
    }
    Eigen::Vector3d a(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    a.normalize();
    return "<axis xyz=\"" + vec(a.x(), a.y(), a.z()) + "\"/>";
  }
  std::string inertial() {
    const double m = uniform(0.2, 5.0);
    const double a = uniform(0.01, 0.2), b = uniform(0.01, 0.2);
    const double c = uniform(std::abs(a - b) + 1e-3, a + b - 1e-3);
    // Rotate the principal moments so products of inertia appear too.
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(uniform(-M_PI, M_PI), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(uniform(-M_PI, M_PI), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    const Eigen::Matrix3d I = R * Eigen::Vector3d(a, b, c).asDiagonal() * R.transpose();
    std::ostringstream s;
    s.precision(17);
    s << "<inertial>" << origin() << "<mass value=\"" << m << "\"/><inertia ixx=\"" << I(0, 0) << "\" ixy=\""
      << I(0, 1) << "\" ixz=\"" << I(0, 2) << "\" iyy=\"" << I(1, 1) << "\" iyz=\"" << I(1, 2) << "\" izz=\""
      << I(2, 2) << "\"/></inertial>";
    return s.str();
  }
};

}  // namespace

std::string randomUrdf(const RandomRobotOptions& o, unsigned seed) {
  Gen g{std::mt19937(seed)};
  struct L { std::string name; bool massless; int children = 0; };
  std::vector<L> links{{"root", true}};
  std::ostringstream joints;
  int moving = 0, k = 0;
  while (moving < o.moving_joints) {
    ++k;
    // Parent: the last link for a chain; for a tree, any link, recent ones more often.
    size_t parent = links.size() - 1;
    if (o.branches && links.size() > 1) {
      const double r = g.uniform(0.0, 1.0);
      parent = static_cast<size_t>(std::floor(r * r * static_cast<double>(links.size())));
      parent = links.size() - 1 - std::min(parent, links.size() - 1);
    }
    const std::string child = "l" + std::to_string(k);
    std::string type = "revolute";
    if (g.chance(o.p_fixed)) type = "fixed";
    else if (g.chance(o.p_prismatic)) type = "prismatic";
    else if (g.chance(o.p_continuous)) type = "continuous";
    if (type != "fixed") ++moving;
    joints << "<joint name=\"j" << k << "\" type=\"" << type << "\"><parent link=\"" << links[parent].name
           << "\"/><child link=\"" << child << "\"/>" << g.origin();
    if (type != "fixed") joints << g.axis(o.p_axis_aligned);
    if (type == "revolute") joints << "<limit lower=\"-2.5\" upper=\"2.5\" effort=\"100\" velocity=\"5\"/>";
    if (type == "prismatic") joints << "<limit lower=\"-0.5\" upper=\"0.5\" effort=\"100\" velocity=\"5\"/>";
    if (type != "fixed" && o.damping && g.chance(0.5))
      joints << "<dynamics damping=\"" << g.uniform(0.0, 0.5) << "\" friction=\"0\"/>";
    joints << "</joint>\n";
    links[parent].children++;
    links.push_back({child, g.chance(o.p_massless)});
  }
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<robot name=\"random" << seed << "\">\n";
  for (const auto& l : links) {
    // A massless leaf would make H singular: leaves always carry mass.
    // The root has mass so the robot also works with a floating base; with a
    // fixed base igms and KDL both ignore it.
    const bool massless = l.name != "root" && l.massless && l.children > 0;
    out << "<link name=\"" << l.name << "\">" << (massless ? "" : g.inertial()) << "</link>\n";
  }
  out << joints.str() << "</robot>\n";
  return out.str();
}

std::string serialChainUrdf(int n) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\"?>\n<robot name=\"chain" << n << "\">\n<link name=\"l0\"/>\n";
  for (int i = 1; i <= n; ++i) {
    const char* axis = (i % 3 == 0) ? "1 0 0" : (i % 3 == 1 ? "0 0 1" : "0 1 0");
    out << "<link name=\"l" << i << "\"><inertial><origin xyz=\"0 0 0.05\"/><mass value=\"1\"/>"
        << "<inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.005\"/></inertial></link>\n"
        << "<joint name=\"j" << i << "\" type=\"revolute\"><parent link=\"l" << (i - 1) << "\"/><child link=\"l" << i
        << "\"/><origin xyz=\"0 0 " << (i == 1 ? 0.0 : 0.1) << "\"/><axis xyz=\"" << axis << "\"/>"
        << "<limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"5\"/></joint>\n";
  }
  out << "</robot>\n";
  return out.str();
}

std::string taperedChainUrdf(double base, double ratio) {
  std::ostringstream out;
  out.precision(17);
  out << "<robot name=\"masses\"><link name=\"l0\"/>";
  for (int i = 1; i <= 12; ++i) {
    const double m = base * std::pow(ratio, -(i - 1) / 11.0), I = 0.01 * m;
    out << "<link name=\"l" << i << "\"><inertial><origin xyz=\"0 0 0.05\"/><mass value=\"" << m
        << "\"/><inertia ixx=\"" << I << "\" ixy=\"0\" ixz=\"0\" iyy=\"" << I << "\" iyz=\"0\" izz=\"" << 0.5 * I
        << "\"/></inertial></link><joint name=\"j" << i << "\" type=\"revolute\"><parent link=\"l" << i - 1
        << "\"/><child link=\"l" << i << "\"/><origin xyz=\"0 0 " << (i == 1 ? 0.0 : 0.1) << "\"/><axis xyz=\""
        << (i % 2 ? "0 1 0" : "1 0 0") << "\"/><limit lower=\"-3\" upper=\"3\" effort=\"1\" velocity=\"1\"/></joint>";
  }
  out << "</robot>";
  return out.str();
}

}  // namespace igms::synthetic
