#pragma once

// Small OpenDRIVE texts for the tests, built from parts.

#include <cstdio>
#include <string>

namespace emrm::opendrive::testing {

inline std::string num(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.17g", value);
  return buffer;
}

/// A <geometry> record around one shape element.
inline std::string geometry(double s, double x, double y, double hdg, double length, const std::string& shape) {
  return "      <geometry s=\"" + num(s) + "\" x=\"" + num(x) + "\" y=\"" + num(y) + "\" hdg=\"" + num(hdg) +
         "\" length=\"" + num(length) + "\">" + shape + "</geometry>\n";
}

inline std::string width(double s_offset, double a, double b = 0, double c = 0, double d = 0) {
  return "<width sOffset=\"" + num(s_offset) + "\" a=\"" + num(a) + "\" b=\"" + num(b) + "\" c=\"" + num(c) +
         "\" d=\"" + num(d) + "\"/>";
}

inline std::string lane(int id, const std::string& type, const std::string& inside) {
  return "          <lane id=\"" + std::to_string(id) + "\" type=\"" + type + "\" level=\"false\">" + inside +
         "</lane>\n";
}

/// A lane section: its left lanes (outer to inner, as files write them) and right lanes.
inline std::string section(double s, const std::string& left, const std::string& right) {
  std::string text = "      <laneSection s=\"" + num(s) + "\">\n";
  if (!left.empty()) text += "        <left>\n" + left + "        </left>\n";
  text += "        <center>\n" + lane(0, "none", "") + "        </center>\n";
  if (!right.empty()) text += "        <right>\n" + right + "        </right>\n";
  return text + "      </laneSection>\n";
}

/// One driving lane each side, 3.5 m.
inline std::string two_lanes() {
  return section(0, lane(1, "driving", width(0, 3.5)), lane(-1, "driving", width(0, 3.5)));
}

inline std::string road(const std::string& id, double length, const std::string& geometries,
                        const std::string& lanes = two_lanes(), const std::string& link = "<link/>",
                        const std::string& junction = "-1") {
  return "  <road id=\"" + id + "\" length=\"" + num(length) + "\" junction=\"" + junction + "\">\n    " + link +
         "\n    <planView>\n" + geometries + "    </planView>\n    <lanes>\n" + lanes + "    </lanes>\n  </road>\n";
}

inline std::string xodr(const std::string& body, int rev_minor = 7) {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<OpenDRIVE>\n  <header revMajor=\"1\" revMinor=\"" +
         std::to_string(rev_minor) + "\" name=\"t\" version=\"1\"/>\n" + body + "</OpenDRIVE>\n";
}

}  // namespace emrm::opendrive::testing
