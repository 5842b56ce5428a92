#include <sstream>

#include "exporters/bop/bop_internal.h"

namespace mocap::exporters::bop {

std::string BopJsonText(const std::map<int, nlohmann::json>& entries) {
  std::ostringstream out;
  out << "{";
  const char* separator = "\n";
  for (const auto& [key, value] : entries) {
    out << separator << "  \"" << key << "\": " << value.dump();
    separator = ",\n";
  }
  out << "\n}\n";
  return out.str();
}

std::string BopJsonListText(const std::vector<nlohmann::json>& items) {
  std::ostringstream out;
  out << "[";
  const char* separator = "\n";
  for (const nlohmann::json& item : items) {
    out << separator << "  " << item.dump();
    separator = ",\n";
  }
  out << "\n]\n";
  return out.str();
}

}  // namespace mocap::exporters::bop
