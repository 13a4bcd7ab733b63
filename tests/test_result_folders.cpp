// Result folders cleave owns: a rerun leaves only the new run's files and removes only what
// the earlier run's manifest lists; another run's result, a killed run and files cleave did
// not write are refused with their reason; a killed run's leftovers go; a write that fails
// names its file and the system's reason; and no path outside the result folder is ever
// written, whatever the scenario's name or --out (checked with strace).
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "cli_helpers.hpp"
#include "folder_test.hpp"
#include "io/result_dir.hpp"

namespace fs = std::filesystem;
using cleave::io::read_manifest;
using cleave::testing::drop_scenario;

namespace {

/// A static specimen (no dynamics): a fraction of a second.
std::string box_scenario(const std::string& name_line) {
  return "[scenario]\n" + name_line + R"(
[specimen]
shape = "box"
size = [6.0, 6.0, 2.0]
[grain]
r = 1.0
r_bar = 0.9
t = 1.0
[orientation]
seed = 3
)";
}

struct Outcome {
  int code = -1;  ///< exit status; -signal when a signal ended it
  std::string output;
};

/// How a child cleave is started: extra environment, a file-size limit, a prefix command
/// (strace), its working folder.
struct Launch {
  std::map<std::string, std::string> env;
  rlim_t file_size_limit = RLIM_INFINITY;
  std::vector<std::string> prefix;
  fs::path cwd;
};

class ResultFolders : public cleave::testing::FolderTest {
 protected:
  /// Starts `cleave ARGS` (stdout and stderr to dir_/log.txt); returns its pid.
  pid_t spawn(const std::vector<std::string>& args, const Launch& how = {}) {
    std::vector<std::string> all = how.prefix;
    all.push_back(CLEAVE_BINARY);
    all.insert(all.end(), args.begin(), args.end());
    const std::string log = (dir_ / "log.txt").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(fd, 1);
      ::dup2(fd, 2);
      for (const auto& [k, v] : how.env) ::setenv(k.c_str(), v.c_str(), 1);
      if (!how.cwd.empty() && ::chdir(how.cwd.c_str()) != 0) ::_exit(126);
      if (how.file_size_limit != RLIM_INFINITY) {
        // A write past the limit fails with EFBIG ("File too large") instead of killing.
        ::signal(SIGXFSZ, SIG_IGN);
        const rlimit limit{how.file_size_limit, how.file_size_limit};
        ::setrlimit(RLIMIT_FSIZE, &limit);
      }
      std::vector<char*> argv;
      for (auto& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execvp(argv[0], argv.data());
      ::_exit(127);
    }
    return pid;
  }
  static int wait_for(pid_t pid) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
  }
  std::string log() const {
    std::ifstream in(dir_ / "log.txt");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }
  Outcome cleave(const std::vector<std::string>& args, const Launch& how = {}) {
    Outcome o;
    o.code = wait_for(spawn(args, how));
    o.output = log();
    return o;
  }

};

/// Every plain file below `dir`, '/'-separated and relative to it.
std::set<std::string> files_below(const fs::path& dir) {
  std::set<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (!e.is_directory()) out.insert(e.path().lexically_relative(dir).generic_string());
  return out;
}

/// What the manifest says the run wrote, with run.toml and SHA256SUMS.
std::set<std::string> listed_with_manifest(const fs::path& dir) {
  std::set<std::string> out{"run.toml", "SHA256SUMS"};
  for (const auto& f : read_manifest(dir).files) out.insert(f.path);
  return out;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_F(ResultFolders, ARerunLeavesOnlyTheNewRunsFiles) {
  // Four frames, then a rerun with two: the earlier run's frames 3 and 4 must not stay
  // beside the new result (nor would cleave.load_result list them).
  const fs::path scenario =
      write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 4\n"));
  const fs::path out = dir_ / "out";
  ASSERT_EQ(cleave({"run", scenario.string(), "--out", out.string(), "--quiet"}).code, 0) << log();
  ASSERT_TRUE(fs::exists(out / "frames" / "bodies_000004.vtp"));
  const Outcome again = cleave(
      {"run", scenario.string(), "--out", out.string(), "--quiet", "--set", "dynamics.frames=2"});
  ASSERT_EQ(again.code, 0) << again.output;
  EXPECT_FALSE(fs::exists(out / "frames" / "bodies_000004.vtp"));
  EXPECT_EQ(files_below(out), listed_with_manifest(out));
}

TEST_F(ResultFolders, AnotherRunsResultIsReplacedOnlyWhenAskedAndOnlyWhatItsManifestLists) {
  const fs::path drop = write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 2\n"));
  const fs::path box = write("box.toml", box_scenario("name = \"box\""));
  const fs::path out = dir_ / "out";
  ASSERT_EQ(cleave({"run", drop.string(), "--out", out.string(), "--quiet"}).code, 0) << log();
  const std::string manifest = bytes_of(out / "run.toml");

  // Another scenario's result: refused, the way out said, nothing touched.
  const Outcome other = cleave({"run", box.string(), "--out", out.string(), "--quiet"});
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_NE(other.output.find("scenario 'drop'"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("--replace"), std::string::npos) << other.output;
  EXPECT_EQ(bytes_of(out / "run.toml"), manifest);

  // A file the earlier run did not write (a note, a foreign table), or one changed since it
  // wrote it: refused by name even with --replace, and left as it is.
  std::ofstream(out / "notes.txt") << "mine";
  const Outcome noted =
      cleave({"run", box.string(), "--out", out.string(), "--quiet", "--replace"});
  EXPECT_EQ(noted.code, 2) << noted.output;
  EXPECT_NE(noted.output.find("notes.txt"), std::string::npos) << noted.output;
  EXPECT_EQ(bytes_of(out / "notes.txt"), "mine");
  EXPECT_EQ(bytes_of(out / "run.toml"), manifest);
  fs::remove(out / "notes.txt");
  std::ofstream(out / "energy.csv", std::ios::app) << "1,2,3\n";
  const Outcome changed =
      cleave({"run", box.string(), "--out", out.string(), "--quiet", "--replace"});
  EXPECT_EQ(changed.code, 2) << changed.output;
  EXPECT_NE(changed.output.find("energy.csv, which has changed"), std::string::npos)
      << changed.output;
  EXPECT_TRUE(fs::exists(out / "energy.csv"));

  // Put back as the run wrote it, --replace replaces it: only the new run's files, and
  // the folders the earlier run made (frames/) are gone with their files.
  const std::string csv = bytes_of(out / "energy.csv");
  std::ofstream(out / "energy.csv", std::ios::binary | std::ios::trunc)
      << csv.substr(0, csv.size() - 6);
  const Outcome replaced =
      cleave({"run", box.string(), "--out", out.string(), "--quiet", "--replace"});
  ASSERT_EQ(replaced.code, 0) << replaced.output;
  EXPECT_EQ(read_manifest(out).facts.at("scenario_name"), "box");
  EXPECT_FALSE(fs::exists(out / "frames"));
  EXPECT_EQ(files_below(out), listed_with_manifest(out));

  // The same for a sweep and a validation: another run's folder is refused by default.
  const fs::path src(CLEAVE_SOURCE_DIR);
  const Outcome validate =
      cleave({"validate", (src / "scenarios/validation/dcb_coarse.toml").string(), "--out",
              out.string(), "--cohesive-beam-only", "--quiet"});
  EXPECT_EQ(validate.code, 2) << validate.output;
  EXPECT_NE(validate.output.find("--replace"), std::string::npos) << validate.output;
}

TEST_F(ResultFolders, AKilledRunsFolderIsRestartableOrANewRunSaysWhy) {
  const fs::path scenario =
      write("drop.toml", drop_scenario("drop", "duration = 0.12\nframes = 12\n"));
  const fs::path out = dir_ / "out";
  const pid_t pid = spawn(
      {"run", scenario.string(), "--out", out.string(), "--quiet", "--checkpoint-every", "5000"});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(out / "checkpoint") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_TRUE(fs::exists(out / "checkpoint"));

  // While it runs, no other run may write there, not even with --replace.
  fs::path side = dir_ / "side";
  fs::create_directories(side);
  std::swap(side, dir_);  // the second run's log apart from the first's
  const Outcome live =
      cleave({"run", scenario.string(), "--out", out.string(), "--quiet", "--replace"});
  std::swap(side, dir_);
  ::kill(pid, SIGKILL);
  ASSERT_EQ(wait_for(pid), -SIGKILL) << "the run ended before it was killed: " << log();
  EXPECT_EQ(live.code, 2) << live.output;
  EXPECT_NE(live.output.find("is writing it now"), std::string::npos) << live.output;
  ASSERT_EQ(read_manifest(out).status, "running");

  // Unfinished writes of the kind the killed run leaves.
  std::ofstream(out / "energy.csv.tmp") << "half";
  std::ofstream(out / "frames" / "bodies_000099.vtp.tmp") << "half";
  fs::create_directories(out / "meshes" / ".cleave-tmp-1-1");
  std::ofstream(out / "meshes" / ".cleave-tmp-1-1" / "grain_0001.obj") << "half";

  // A new run is refused and says how to go on.
  const Outcome fresh = cleave({"run", scenario.string(), "--out", out.string(), "--quiet"});
  EXPECT_EQ(fresh.code, 2) << fresh.output;
  EXPECT_NE(fresh.output.find("did not end"), std::string::npos) << fresh.output;
  EXPECT_NE(fresh.output.find("cleave restart " + out.string()), std::string::npos) << fresh.output;
  EXPECT_EQ(read_manifest(out).status, "running");

  // A copy of the killed folder (times kept) is replaced on request: only the new files.
  const fs::path copy = dir_ / "copy";
  ASSERT_EQ(std::system(("cp -a " + out.string() + " " + copy.string()).c_str()), 0);
  // As if another host had written it (a shared file system): cleave cannot ask that host
  // whether the run is alive, so only --replace says it is gone.
  std::string text = bytes_of(copy / "run.toml");
  const auto at = text.find("host = ");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at, text.find('\n', at) - at, "host = 'another-host'");
  std::ofstream(copy / "run.toml", std::ios::binary | std::ios::trunc) << text;
  fs::last_write_time(copy / "run.toml", fs::last_write_time(out / "run.toml"));
  const Outcome elsewhere = cleave({"run", scenario.string(), "--out", copy.string(), "--quiet"});
  EXPECT_EQ(elsewhere.code, 2) << elsewhere.output;
  EXPECT_NE(elsewhere.output.find("on host another-host"), std::string::npos) << elsewhere.output;
  const Outcome replaced =
      cleave({"run", scenario.string(), "--out", copy.string(), "--quiet", "--replace"});
  ASSERT_EQ(replaced.code, 0) << replaced.output;
  EXPECT_EQ(files_below(copy), listed_with_manifest(copy));

  // The restart ends the run where the uninterrupted one ends, and leaves no leftovers.
  const Outcome restarted = cleave({"restart", out.string(), "--quiet"});
  ASSERT_EQ(restarted.code, 0) << restarted.output;
  const auto m = read_manifest(out);
  EXPECT_EQ(m.status, "finished");
  EXPECT_EQ(m.facts.at("final_state_hash"), read_manifest(copy).facts.at("final_state_hash"));
  for (const std::string& f : files_below(out)) {
    EXPECT_EQ(f.find(".tmp"), std::string::npos) << f;
    EXPECT_EQ(f.find(".cleave-tmp-"), std::string::npos) << f;
  }
}

TEST_F(ResultFolders, ScratchFoldersOfKilledMpiRanksAreRemovedByTheNextRun) {
  // The ranks above 0 of `mpirun cleave run` work in TMPDIR/cleave-rankN-HOST-PID; a killed
  // run leaves them. The next run on this host removes those whose process is gone.
  const fs::path tmp = dir_ / "tmp";
  fs::create_directories(tmp);
  std::array<char, 256> host{};
  ::gethostname(host.data(), host.size() - 1);
  const pid_t gone = ::fork();
  if (gone == 0) ::_exit(0);
  wait_for(gone);  // a pid whose process has ended
  const std::string g = std::to_string(gone), me = std::to_string(::getpid());
  const std::vector<std::string> stale = {"cleave-rank1-" + std::string(host.data()) + "-" + g,
                                          "cleave-rank2-" + g};  // as earlier versions named them
  const std::vector<std::string> kept = {
      "cleave-rank1-" + std::string(host.data()) + "-" + me,  // alive
      "cleave-rank1-another-host-" + g,                       // not this host's to judge
      "cleave-rankings-" + g, "notes-" + g};
  for (const auto& n : stale) {
    fs::create_directories(tmp / n / "frames");
    std::ofstream(tmp / n / "run.toml") << "status = \"running\"\n";
  }
  for (const auto& n : kept) fs::create_directories(tmp / n);
  const fs::path box = write("box.toml", box_scenario("name = \"box\""));
  Launch how;
  how.env["TMPDIR"] = tmp.string();
  const Outcome run =
      cleave({"run", box.string(), "--out", (dir_ / "out").string(), "--quiet"}, how);
  ASSERT_EQ(run.code, 0) << run.output;
  for (const auto& n : stale) EXPECT_FALSE(fs::exists(tmp / n)) << n;
  for (const auto& n : kept) EXPECT_TRUE(fs::exists(tmp / n)) << n;
}

TEST_F(ResultFolders, AWriteThatFailsNamesTheFileAndTheSystemsReasonAndTheRunEndsFailed) {
  // Files above 8000 bytes cannot be written (EFBIG, as a full disk gives ENOSPC): the
  // manifest and scenario fit, the fragments' mesh does not.
  const fs::path box = write("box.toml", box_scenario("name = \"box\""));
  const fs::path out = dir_ / "out";
  Launch how;
  how.file_size_limit = 8000;
  const Outcome run = cleave({"run", box.string(), "--out", out.string(), "--quiet"}, how);
  EXPECT_EQ(run.code, 1) << run.output;
  const std::string reason = std::strerror(EFBIG);
  EXPECT_NE(run.output.find("meshes/fragments.obj"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(reason), std::string::npos) << run.output;
  const auto m = read_manifest(out);
  EXPECT_EQ(m.status, "failed");
  EXPECT_NE(m.reason.find(reason), std::string::npos) << m.reason;
  for (const std::string& f : files_below(out)) EXPECT_EQ(f.find(".tmp"), std::string::npos) << f;

  // The manifest itself cannot be written: no run.toml says "running", and the message
  // names it.
  how.file_size_limit = 200;
  const fs::path out2 = dir_ / "out2";
  const Outcome none = cleave({"run", box.string(), "--out", out2.string(), "--quiet"}, how);
  EXPECT_EQ(none.code, 1) << none.output;
  EXPECT_NE(none.output.find("run.toml"), std::string::npos) << none.output;
  EXPECT_NE(none.output.find(reason), std::string::npos) << none.output;
  EXPECT_TRUE(!fs::exists(out2 / "run.toml") || read_manifest(out2).status == "failed");
}

namespace {

/// The paths a traced process (strace -f -e trace=file) wrote, created, renamed or removed,
/// absolute: each openat with O_WRONLY, O_RDWR, O_CREAT or O_TRUNC, and each creat, mkdir,
/// rename, link, unlink, rmdir, truncate, chmod, utime. Relative paths are taken from `cwd`
/// (cleave never changes its folder).
std::vector<fs::path> written_paths(const fs::path& trace, const fs::path& cwd) {
  std::vector<fs::path> out;
  std::ifstream in(trace);
  std::string line;
  static const std::regex call(R"((\w+)\((.*))");
  static const std::regex quoted(R"re("((?:[^"\\]|\\.)*)")re");
  while (std::getline(in, line)) {
    std::smatch m;
    const auto paren = line.find('(');
    if (paren == std::string::npos) continue;
    auto start = line.find_last_of(" ]", paren);
    start = start == std::string::npos ? 0 : start + 1;
    const std::string name = line.substr(start, paren - start);
    const std::string args = line.substr(paren + 1);
    const bool opens = name == "open" || name == "openat" || name == "openat2";
    const bool changes = name == "creat" || name.rfind("mkdir", 0) == 0 ||
                         name.rfind("rename", 0) == 0 || name.rfind("link", 0) == 0 ||
                         name.rfind("symlink", 0) == 0 || name.rfind("unlink", 0) == 0 ||
                         name == "rmdir" || name.rfind("truncate", 0) == 0 ||
                         name.rfind("chmod", 0) == 0 || name.rfind("fchmodat", 0) == 0 ||
                         name.rfind("utime", 0) == 0 || name.rfind("chown", 0) == 0 ||
                         name.rfind("fchownat", 0) == 0 || name.rfind("mknod", 0) == 0;
    if (!opens && !changes) continue;
    if (opens && args.find("O_WRONLY") == std::string::npos &&
        args.find("O_RDWR") == std::string::npos && args.find("O_CREAT") == std::string::npos &&
        args.find("O_TRUNC") == std::string::npos)
      continue;
    for (auto it = std::sregex_iterator(args.begin(), args.end(), quoted);
         it != std::sregex_iterator(); ++it) {
      const fs::path p((*it)[1].str());
      if (p.empty()) continue;
      out.push_back(p.is_absolute() ? p : cwd / p);
    }
  }
  return out;
}

bool below(const fs::path& p, const fs::path& folder) {
  const fs::path a = fs::weakly_canonical(p), f = fs::weakly_canonical(folder);
  const auto [end, _] = std::mismatch(f.begin(), f.end(), a.begin(), a.end());
  return end == f.end();
}

}  // namespace

TEST_F(ResultFolders, NoPathOutsideTheResultFolderIsEverWrittenWhateverTheNameOrOut) {
  if (std::system("strace -V > /dev/null 2>&1") != 0) GTEST_SKIP() << "strace is not installed";
  // The sandbox: a working folder, a home, and something outside both that a hostile
  // name or --out might reach.
  const fs::path work = dir_ / "work", home = dir_ / "home", outside = dir_ / "outside";
  for (const auto& d : {work, home, outside / "target"}) fs::create_directories(d);
  std::ofstream(outside / "precious.txt") << "keep";
  fs::create_directory_symlink(outside / "target", work / "link");
  std::ofstream(work / "a_file") << "not a folder";
  Launch how;
  how.cwd = work;
  how.env["HOME"] = home.string();
  how.env["TMPDIR"] = (dir_ / "tmp").string();
  fs::create_directories(dir_ / "tmp");
  const fs::path trace = dir_ / "trace.txt";
  how.prefix = {"strace", "-f", "-qq", "-o", trace.string(), "-e", "trace=file"};

  // Names that would lead out of results/ (or hide in it) are refused before anything is
  // written; so are outs that are no folder of cleave's.
  struct Case {
    std::string name_line;         ///< the scenario's [scenario] name line
    std::vector<std::string> out;  ///< --out and its value, or none
    bool runs;        ///< expected to run (into the folder it names) rather than be refused
    fs::path folder;  ///< where a run may write
  };
  const std::vector<Case> cases = {
      {R"(name = "../x")", {}, false, {}},
      {R"(name = "../../../../../../../tmp/cleave_escape")", {}, false, {}},
      {R"(name = "/abs")", {}, false, {}},
      {R"(name = "a/b")", {}, false, {}},
      {R"(name = "a\\b")", {}, false, {}},
      {R"(name = ".hidden")", {}, false, {}},
      {R"(name = "..")", {}, false, {}},
      {R"(name = ".")", {}, false, {}},
      {R"(name = "")", {}, false, {}},
      {R"(name = "x\ny")", {}, true, work / "results"},
      {R"(name = "x\u0000y")", {}, false, {}},
      {R"(name = "ok")", {"--out", "/"}, false, {}},
      {R"(name = "ok")", {"--out", home.string()}, false, {}},
      {R"(name = "ok")", {"--out", "."}, false, {}},
      {R"(name = "ok")", {"--out", ".."}, false, {}},
      {R"(name = "ok")", {"--out", "a_file"}, false, {}},
      {R"(name = "ok")", {"--out", "link"}, true, outside / "target"},
      {R"(name = "ok")", {"--out", "~"}, true, work / "~"},  // no shell: a folder named ~
      {R"(name = "ok")", {}, true, work / "results" / "ok"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name_line + (c.out.empty() ? "" : " --out " + c.out[1]));
    const fs::path scenario = write("hostile.toml", box_scenario(c.name_line));
    std::vector<std::string> args = {"run", scenario.string(), "--quiet"};
    args.insert(args.end(), c.out.begin(), c.out.end());
    const Outcome run = cleave(args, how);
    EXPECT_EQ(run.code, c.runs ? 0 : 2) << run.output;
    for (const fs::path& p : written_paths(trace, work)) {
      if (p.string().rfind("/dev/", 0) == 0) continue;  // the terminal, /dev/null
      EXPECT_TRUE(c.runs && below(p, c.folder)) << "wrote " << p.string();
    }
  }
  EXPECT_EQ(bytes_of(outside / "precious.txt"), "keep");

  // An earlier result whose frames/ was made a link out of it: refused, nothing written
  // through the link.
  const fs::path drop = write("drop.toml", drop_scenario("drop", "duration = 6e-5\nframes = 2\n"));
  const fs::path res = work / "res";
  ASSERT_EQ(cleave({"run", drop.string(), "--out", res.string(), "--quiet"}).code, 0) << log();
  fs::rename(res / "frames", outside / "frames");
  fs::create_directory_symlink(outside / "frames", res / "frames");
  const Outcome linked = cleave({"run", drop.string(), "--out", res.string(), "--quiet"}, how);
  EXPECT_EQ(linked.code, 2) << linked.output;
  EXPECT_NE(linked.output.find("frames"), std::string::npos) << linked.output;
  for (const fs::path& p : written_paths(trace, work)) {
    if (p.string().rfind("/dev/", 0) == 0) continue;
    EXPECT_TRUE(below(p, res) && !below(p, res / "frames")) << "wrote " << p.string();
  }
  EXPECT_TRUE(fs::exists(outside / "frames" / "bodies_000001.vtp"));
}

TEST_F(ResultFolders, AMeasurementIsAResultItsNextRunReplaces) {
  // `cleave measure` adds its tables to the run's manifest, and a loading-rate study's
  // folder (one run per rate, the table) is a result of its own: both run again in place
  // and hold only the new files.
  const std::string elastic = (fs::path(CLEAVE_SOURCE_DIR) / "scenarios/materials/sic_elastic.toml").string();
  for (const bool converge : {false, true}) {
    SCOPED_TRACE(converge ? "--converge" : "one run");
    const fs::path out = dir_ / (converge ? "study" : "one");
    std::vector<std::string> args = {"measure", "elastic", elastic, "--out", out.string(), "--quiet"};
    if (converge) args.insert(args.end(), {"--converge", "--max-runs", "2"});
    for (int time = 0; time < 2; ++time) {
      const Outcome run = cleave(args);
      ASSERT_EQ(run.code, 0) << run.output;
      EXPECT_EQ(read_manifest(out).status, "finished");
      EXPECT_EQ(files_below(out), listed_with_manifest(out));
    }
    EXPECT_TRUE(fs::exists(out / (converge ? "convergence.csv" : "measure.toml")));
  }
}

TEST_F(ResultFolders, CalibrateWritesOnlyInAFolderItOwns) {
  // `cleave calibrate` wrote its trials and tables into any --out, / included; its folder is
  // now a result of its own, checked before anything runs.
  const std::string file = (fs::path(CLEAVE_SOURCE_DIR) / "scenarios/materials/sic_calibration.toml").string();
  const Outcome root = cleave({"calibrate", file, "--out", "/", "--quiet"});
  EXPECT_EQ(root.code, 2) << root.output;
  EXPECT_NE(root.output.find("is the file system's root"), std::string::npos) << root.output;
  const fs::path foreign = dir_ / "foreign";
  fs::create_directories(foreign);
  std::ofstream(foreign / "notes.txt") << "mine";
  const Outcome other = cleave({"calibrate", file, "--out", foreign.string(), "--quiet"});
  EXPECT_EQ(other.code, 2) << other.output;
  EXPECT_EQ(files_below(foreign), std::set<std::string>{"notes.txt"});
}
