// PEER NGA strong-motion records (.AT2), the format of the PEER Ground Motion Database
// (Ancheta et al. 2014, PEER report 2013/03, appendix on file formats).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "framework/core/error.hpp"
#include "framework/seismic/ground_motion.hpp"

namespace rockdem::seismic {
namespace {

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}

// The size of the record's unit in m/s^2, from the third header line.
double at2_unit(const std::string& line, const std::string& where) {
  const std::string u = upper(line);
  if (u.find("UNITS OF G") != std::string::npos || std::regex_search(u, std::regex("\\bIN G\\b"))) return 9.80665;
  if (u.find("CM/S") != std::string::npos || u.find("CM/SEC") != std::string::npos) return 0.01;
  if (u.find("M/S") != std::string::npos) return 1.0;
  throw InputError(where + ": the header line '" + line + "' names no acceleration unit; a PEER .AT2 record says "
                   "\"ACCELERATION TIME SERIES IN UNITS OF G\" (also read: cm/s^2, m/s^2)");
}

}  // namespace

GroundMotion load_peer_at2(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the record (no such file or not readable)");
  std::string header[4];
  for (int i = 0; i < 4; ++i)
    if (!std::getline(in, header[i]))
      throw InputError(path + ": a PEER .AT2 record has four header lines; the file ends at line " + std::to_string(i + 1));
  const double unit = at2_unit(header[2], path + ":3");
  // NGA-West2: "NPTS=  4000, DT=   .0100 SEC"; older NGA files: "  4000    0.0100    NPTS, DT".
  std::smatch m;
  const std::string h4 = upper(header[3]);
  long npts = 0;
  double dt = 0.0;
  const std::regex named("NPTS\\s*=\\s*([0-9]+)\\s*,?\\s*DT\\s*=\\s*([-+0-9.eE]+)");
  const std::regex plain("^\\s*([0-9]+)\\s+([-+0-9.eE]+)\\s+NPTS");
  if (std::regex_search(h4, m, named) || std::regex_search(h4, m, plain)) {
    npts = std::stol(m[1].str());
    dt = std::stod(m[2].str());
  } else {
    throw InputError(path + ":4: expected the number of points and the time step, as \"NPTS=  4000, DT=   .0100 SEC\"; got '" +
                     header[3] + "'");
  }
  if (npts < 2 || npts > 100000000) throw InputError(path + ":4: NPTS = " + std::to_string(npts) + " is not a record length (2 or more)");
  if (!(dt > 0.0) || !std::isfinite(dt)) throw InputError(path + ":4: DT must be a positive time step in seconds");
  GroundMotion g;
  g.source = path;
  g.column_name = "PEER AT2";
  g.dt = dt;
  g.acc.reserve(static_cast<std::size_t>(npts));
  std::string line;
  int line_no = 4;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream ls(line);
    std::string tok;
    while (ls >> tok) {
      char* end = nullptr;
      const double v = std::strtod(tok.c_str(), &end);
      if (end != tok.c_str() + tok.size() || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(line_no) + ": '" + tok + "' is not a finite number");
      if (static_cast<long>(g.acc.size()) == npts)
        throw InputError(path + ":" + std::to_string(line_no) + ": more values than NPTS = " + std::to_string(npts));
      g.acc.push_back(v * unit);
    }
  }
  if (static_cast<long>(g.acc.size()) != npts)
    throw InputError(path + ": " + std::to_string(g.acc.size()) + " values, but the header gives NPTS = " + std::to_string(npts));
  return g;
}

}  // namespace rockdem::seismic
