#include "results_journal.hpp"

#include <cinttypes>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace dynweigh::tools::grid {
namespace {

const char* const kHeaderPrefix = "# dynweigh grid journal v1: ";

std::string checksum(const std::string& key, const std::string& row) {
  std::uint64_t hash = 14695981039346656037ull;
  const auto mix = [&hash](const std::string& text) {
    for (unsigned char c : text) {
      hash ^= c;
      hash *= 1099511628211ull;
    }
  };
  mix(key);
  mix("\t");
  mix(row);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016" PRIx64, hash);
  return hex;
}

std::string header_line(const std::string& signature) { return kHeaderPrefix + signature + "\n"; }

void write_all(std::FILE* file, const std::string& text, const std::string& path) {
  if (std::fwrite(text.data(), 1, text.size(), file) != text.size()) throw std::runtime_error("cannot write " + path);
}

}  // namespace

void check_journal_field(const std::string& what, const std::string& text) {
  if (text.find_first_of("\t\r\n") != std::string::npos) {
    throw std::invalid_argument(what + " '" + text + "' holds a tab or a line break");
  }
}

std::string journal_line(const std::string& key, const std::string& row) {
  return key + "\t" + row + "\t" + checksum(key, row) + "\n";
}

bool parse_journal_line(const std::string& line, std::string& key, std::string& row) {
  const auto first = line.find('\t');
  const auto last = line.rfind('\t');
  if (first == std::string::npos || first == last) return false;
  key = line.substr(0, first);
  row = line.substr(first + 1, last - first - 1);
  return line.substr(last + 1) == checksum(key, row);
}

JournalContents read_journal(const std::string& path, const std::string& signature) {
  JournalContents contents;
  std::ifstream in(path, std::ios::binary);
  if (!in) return contents;
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  // Only lines that end in a line break are whole; what follows the last one was cut short.
  std::size_t start = 0;
  bool header = true;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1) {
    const std::string line = text.substr(start, end - start);
    if (header) {
      if (line + "\n" != header_line(signature)) {
        const std::string prefix = kHeaderPrefix;
        const std::string theirs = line.compare(0, prefix.size(), prefix) == 0 ? line.substr(prefix.size()) : line;
        throw std::runtime_error("journal " + path + " was written for another grid ('" + theirs + "', not '" +
                                 signature + "'): remove it or name another --journal");
      }
      header = false;
      continue;
    }
    std::string key, row;
    if (parse_journal_line(line, key, row)) {
      contents.rows.emplace(key, row);
    } else {
      ++contents.dropped_lines;
    }
  }
  if (start < text.size() && !header) ++contents.dropped_lines;
  return contents;
}

JournalWriter::JournalWriter(const std::string& path, const std::string& signature, const JournalContents& kept)
    : path_(path) {
  check_journal_field("journal signature", signature);
  const std::string temporary = path + ".tmp";
  std::FILE* fresh = std::fopen(temporary.c_str(), "wb");
  if (!fresh) throw std::runtime_error("cannot write journal " + temporary + ": " + std::strerror(errno));
  try {
    write_all(fresh, header_line(signature), temporary);
    for (const auto& [key, row] : kept.rows) write_all(fresh, journal_line(key, row), temporary);
  } catch (...) {
    std::fclose(fresh);
    throw;
  }
  if (std::fclose(fresh) != 0 || std::rename(temporary.c_str(), path.c_str()) != 0) {
    throw std::runtime_error("cannot write journal " + path + ": " + std::strerror(errno));
  }
  file_ = std::fopen(path.c_str(), "ab");
  if (!file_) throw std::runtime_error("cannot append to journal " + path + ": " + std::strerror(errno));
}

JournalWriter::~JournalWriter() {
  if (file_) std::fclose(file_);
}

void JournalWriter::append(const std::string& key, const std::string& row) {
  write_all(file_, journal_line(key, row), path_);
  if (std::fflush(file_) != 0) throw std::runtime_error("cannot write journal " + path_);
}

}  // namespace dynweigh::tools::grid
