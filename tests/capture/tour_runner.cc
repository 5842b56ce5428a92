#include "tour_runner.h"

#include <signal.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace mocap::testing {
namespace {

namespace fs = std::filesystem;

std::string Trim(const std::string& text) {
  const size_t begin = text.find_first_not_of(" \t");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t") - begin + 1);
}

std::vector<std::string> Words(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string word; in >> word;) words.push_back(word);
  return words;
}

void ReplaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
}

}  // namespace

std::vector<std::string> ReadTourCommands(const fs::path& doc, const std::string& marker) {
  std::ifstream in(doc);
  std::string line;
  while (std::getline(in, line) && line.find(marker) == std::string::npos) {
  }
  if (!in) throw std::runtime_error(doc.string() + ": no line with '" + marker + "'");
  while (std::getline(in, line) && line.rfind("```", 0) != 0) {
  }
  std::vector<std::string> commands;
  std::string pending;
  while (std::getline(in, line) && line.rfind("```", 0) != 0) {
    const std::string text = Trim(line.substr(0, line.find(" #")));
    if (text.empty() || text[0] == '#') continue;
    pending += text;
    if (pending.back() == '\\') {
      pending.back() = ' ';
      continue;
    }
    commands.push_back(pending);
    pending.clear();
  }
  if (commands.empty()) throw std::runtime_error(doc.string() + ": the block after '" + marker + "' holds no command");
  return commands;
}

std::string TourRunner::Substitute(std::string text) const {
  for (const auto& [name, value] : options_.variables) ReplaceAll(text, "$" + name, value);
  for (const auto& [from, to] : options_.replace) ReplaceAll(text, from, to);
  return text;
}

void TourRunner::PatchFiles() const {
  for (const fs::path& file : options_.files) {
    if (!fs::exists(file)) continue;
    std::stringstream text;
    text << std::ifstream(file).rdbuf();
    std::string patched = text.str();
    for (const auto& [from, to] : options_.replace) ReplaceAll(patched, from, to);
    if (patched != text.str()) std::ofstream(file, std::ios::trunc) << patched;
  }
}

void TourRunner::Run(const std::string& doc_line) {
  static const std::regex assignment("^[A-Za-z_][A-Za-z_0-9]*=\\S*$");
  if (std::regex_match(doc_line, assignment)) return;  // the runner's own variables stand in
  std::string line = Substitute(doc_line);
  const bool background = line.back() == '&';
  if (background) line = Trim(line.substr(0, line.size() - 1));
  std::vector<std::string> words = Words(line);
  if (words.front() == "kill") return Kill({words.begin() + 1, words.end()});
  std::map<std::string, std::string> env;
  while (!words.empty() && std::regex_match(words.front(), assignment)) {
    const size_t equals = words.front().find('=');
    env[words.front().substr(0, equals)] = words.front().substr(equals + 1);
    words.erase(words.begin());
  }
  if (words.front() == "mocaplabel") words.front() = options_.mocaplabel;
  else words = {"/bin/sh", "-c", line};
  Spawn(words, env, background, doc_line);
  PatchFiles();
}

void TourRunner::Spawn(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env, bool background,
                       const std::string& line) {
  const fs::path log = options_.log_dir / (std::to_string(++count_) + ".log");
  auto process = std::make_unique<ChildProcess>(argv, env, log);
  if (background) {
    if (!process->ReadLine(options_.timeout_s * 1000))
      throw std::runtime_error("`" + line + "` printed nothing (it should say where it listens); log:\n" + process->Log());
    background_.push_back(std::move(process));
    return;
  }
  std::string out;
  while (const std::optional<std::string> printed = process->ReadLine(options_.timeout_s * 1000)) out += *printed + "\n";
  const std::optional<int> status = process->Wait(options_.timeout_s * 1000);
  outputs_.push_back(out);
  if (status != 0)
    throw std::runtime_error("`" + line + "` exited with " + (status ? std::to_string(*status) : "a timeout") + "; stdout:\n" +
                             out + "log:\n" + process->Log());
}

void TourRunner::Kill(const std::vector<std::string>& jobs) {
  for (const std::string& job : jobs) {
    const size_t index = std::stoul(job.substr(1)) - 1;  // %N: the N-th background command
    if (job[0] != '%' || index >= background_.size()) throw std::runtime_error("kill " + job + ": no such job");
    ChildProcess& process = *background_[index];
    process.Signal(SIGTERM);
    const std::optional<int> status = process.Wait(20000);
    if (status != 0) throw std::runtime_error("kill " + job + ": it exited with " + (status ? std::to_string(*status) : "a timeout") +
                                              "; log:\n" + process.Log());
  }
}

}  // namespace mocap::testing
