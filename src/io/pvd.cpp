#include "io/pvd.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <fmt/core.h>

#include "common/atomic_file.hpp"
#include "common/error.hpp"
#include "io/vtk_xml.hpp"

namespace settle::io {

namespace fs = std::filesystem;

PvdCollection::PvdCollection(fs::path pvd_path) : path_(std::move(pvd_path)) {}

PvdCollection PvdCollection::resume(fs::path pvd_path, double keep_until_time_si) {
  PvdCollection collection(std::move(pvd_path));
  const fs::path& path = collection.path_;
  if (!fs::exists(path)) return collection;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot read", path.string()));
  std::stringstream text;
  text << in.rdbuf();
  const std::string content = text.str();
  if (content.find("<VTKFile type=\"Collection\"") == std::string::npos)
    throw InputError(fmt::format("{}: not a ParaView data collection (.pvd)", path.string()));

  // Entries as rewrite() writes them: one DataSet element per line, timestep first, file last.
  static const std::regex dataset(R"re(<DataSet timestep="([^"]*)"[^>]*\sfile="([^"]*)"\s*/>)re");
  std::size_t dropped = 0;
  for (auto it = std::sregex_iterator(content.begin(), content.end(), dataset); it != std::sregex_iterator(); ++it) {
    const std::string time_text = (*it)[1].str();
    char* end = nullptr;
    const double time_si = std::strtod(time_text.c_str(), &end);
    if (time_text.empty() || *end != '\0' || !std::isfinite(time_si))
      throw InputError(fmt::format("{}: bad timestep \"{}\"", path.string(), time_text));
    if (time_si > keep_until_time_si) {
      ++dropped;
      continue;
    }
    if (!collection.entries_.empty() && time_si <= collection.entries_.back().time_si)
      throw InputError(fmt::format("{}: timesteps do not increase at {}", path.string(), time_text));
    collection.entries_.push_back({time_si, xml_unescaped((*it)[2].str())});
  }
  if (dropped > 0) collection.rewrite();
  return collection;
}

void PvdCollection::add(double time_si, const fs::path& file) {
  if (!std::isfinite(time_si))
    throw std::invalid_argument(fmt::format("PvdCollection::add: time {} is not finite", time_si));
  if (!entries_.empty() && time_si <= entries_.back().time_si)
    throw std::invalid_argument(fmt::format("PvdCollection::add: time {} does not follow the last entry's {}", time_si,
                                            entries_.back().time_si));
  const fs::path directory = fs::absolute(path_).lexically_normal().parent_path();
  const fs::path absolute_file = fs::absolute(file).lexically_normal();
  fs::path relative = absolute_file.lexically_relative(directory);
  if (relative.empty()) relative = absolute_file;  // no relative route (e.g. another drive root)
  entries_.push_back({time_si, relative.generic_string()});
  try {
    rewrite();
  } catch (...) {
    entries_.pop_back();  // the collection stays as the file on disk
    throw;
  }
}

void PvdCollection::rewrite() const {
  AtomicFile file(path_);
  std::ostream& out = file.stream();
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"" << vtk_byte_order()
      << "\">\n  <Collection>\n";
  for (const Entry& entry : entries_)
    out << fmt::format("    <DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", vtk_number(entry.time_si),
                       xml_escaped(entry.file));
  out << "  </Collection>\n</VTKFile>\n";
  file.commit();
}

}  // namespace settle::io
