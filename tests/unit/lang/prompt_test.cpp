// Drives the real prompt through a pseudo-terminal, as a person at a keyboard would.
#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <fstream>
#include <poll.h>
#include <pty.h>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "../time_scale.h"

namespace {

// A time limit of the tests, `seconds` on an idle machine (tests/unit/time_scale.h).
std::chrono::steady_clock::duration limit(double seconds) {
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(seconds * odec::test::time_scale()));
}

class Terminal {
public:
    explicit Terminal(const std::string& home) {
        pid_ = forkpty(&fd_, nullptr, nullptr, nullptr);
        if (pid_ == 0) {
            setenv("HOME", home.c_str(), 1);
            setenv("TERM", "dumb", 1);
            unsetenv("ODEC_HISTORY");
            execl(ODEC_BINARY, ODEC_BINARY, static_cast<char*>(nullptr));
            _exit(127);
        }
    }
    ~Terminal() {
        if (pid_ > 0) {
            kill(pid_, SIGKILL);
            waitpid(pid_, nullptr, 0);
        }
        if (fd_ >= 0) close(fd_);
    }
    void type(const std::string& s) { ASSERT_EQ(write(fd_, s.data(), s.size()), static_cast<ssize_t>(s.size())); }
    // Reads until `what` has appeared in the output since the last call, or 10 s pass (times
    // the time scale, as every wait below).
    bool expect(const std::string& what) {
        const auto end = std::chrono::steady_clock::now() + limit(10);
        while (std::chrono::steady_clock::now() < end) {
            const size_t at = seen_.find(what, from_);
            if (at != std::string::npos) {
                from_ = at + what.size();
                return true;
            }
            pollfd p{fd_, POLLIN, 0};
            if (poll(&p, 1, 100) > 0) {
                char buf[4096];
                const ssize_t n = read(fd_, buf, sizeof buf);
                if (n <= 0) break;
                seen_.append(buf, n);
            }
        }
        return false;
    }
    // Exit status of the program, or -1 when it has not ended within 10 s (it is then killed).
    int wait_exit() {
        int status = 0;
        const auto end = std::chrono::steady_clock::now() + limit(10);
        while (std::chrono::steady_clock::now() < end) {
            // Keep draining output so that the program never blocks writing to the terminal.
            pollfd p{fd_, POLLIN, 0};
            if (poll(&p, 1, 10) > 0 && (p.revents & POLLIN)) {
                char buf[4096];
                const ssize_t n = read(fd_, buf, sizeof buf);
                if (n > 0) seen_.append(buf, n);
            } else {
                usleep(10000);
            }
            if (waitpid(pid_, &status, WNOHANG) == pid_) {
                pid_ = -1;
                if (WIFSIGNALED(status)) {
                    seen_ += "\n[killed by signal " + std::to_string(WTERMSIG(status)) + "]";
                    return -1000 - WTERMSIG(status);
                }
                return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
            }
        }
        return -1;
    }
    const std::string& seen() const { return seen_; }

private:
    int fd_ = -1;
    pid_t pid_ = -1;
    std::string seen_;
    size_t from_ = 0;
};

std::string temp_home() {
    char tmpl[] = "/tmp/odec-home-XXXXXX";
    return mkdtemp(tmpl);
}

} // namespace

TEST(Prompt, CompletesCommandsAndKeywords) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("pro\t");
    ASSERT_TRUE(t.expect("property ")) << t.seen();
    t.type("mat=1 den\t");
    ASSERT_TRUE(t.expect("density ")) << t.seen();
    t.type("2000\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("print info\n");
    ASSERT_TRUE(t.expect("materials:  1 (dens 2000)")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("\x04"); // Ctrl-D leaves
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, FishDefinitionsSpanLinesAndNamesComplete) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    // Lines of a definition wait for its 'end' before anything runs.
    t.type("def halfway(a, b)\n");
    ASSERT_TRUE(t.expect("...> ")) << t.seen();
    t.type("  halfway = (a + b) / 2.0\n");
    ASSERT_TRUE(t.expect("...> ")) << t.seen();
    t.type("end\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("@answer = halfway(1, 4)\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    // @ and the start of a FISH name complete to the name.
    t.type("list @ans\t");
    ASSERT_TRUE(t.expect("answer")) << t.seen();
    t.type("\n");
    ASSERT_TRUE(t.expect("answer = 2.5")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, CtrlCStopsARunawayFishLoop) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("def spin\n  loop while 1 = 1\n    x = 1\n  endloop\nend\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("@spin\n");
    usleep(300000);
    t.type("\x03");
    ASSERT_TRUE(t.expect("interrupted by Ctrl-C")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("@y = 2\nlist y\n");
    ASSERT_TRUE(t.expect("y = 2")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, ContinuationPromptAfterAmpersand) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> "));
    t.type("poly brick 0 1 &\n");
    ASSERT_TRUE(t.expect("...> ")) << t.seen();
    t.type("0 1 0 1\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("print block\n");
    ASSERT_TRUE(t.expect("1 of 1 blocks")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
    // The history file keeps the joined command for the next session.
    std::ifstream h(home + "/.odec_history");
    std::string all((std::istreambuf_iterator<char>(h)), std::istreambuf_iterator<char>());
    EXPECT_NE(all.find("print block"), std::string::npos) << all;
}

TEST(Prompt, ErrorsDoNotEndTheSessionAndCtrlCClearsTheLine) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> "));
    t.type("prop mat=1 dens=-5\n");
    ASSERT_TRUE(t.expect("'density' must be > 0 (got -5)")) << t.seen();
    ASSERT_TRUE(t.expect("odec> "));
    t.type("grav 0 0 -10 junk");
    ASSERT_TRUE(t.expect("junk")) << t.seen();
    t.type("\x03"); // Ctrl-C drops the half-typed line
    ASSERT_TRUE(t.expect("^C")) << t.seen();
    t.type("print info\n");
    ASSERT_TRUE(t.expect("gravity:    (0,0,0)")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, CtrlCStopsALongStepAndTheSessionGoesOn) {
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> "));
    t.type("poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nset dt 1e-9\nstep 2000000000\n");
    ASSERT_TRUE(t.expect("step 2000000000")) << t.seen(); // the echo of the typed line
    usleep(300000);
    t.type("\x03");
    ASSERT_TRUE(t.expect("interrupted after")) << t.seen();
    ASSERT_TRUE(t.expect("odec> "));
    t.type("print info\n");
    ASSERT_TRUE(t.expect("step:")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, CtrlCInACalledScriptStopsTheWholeScript) {
    // outer.dat calls inner.dat, whose long step is interrupted: neither script goes on, the
    // session does, and the model is whole.
    const std::string home = temp_home();
    {
        std::ofstream(home + "/inner.dat") << "poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nset dt 1e-9\n"
                                              "step 2000000000\ntitle 'inner went on'\n";
        std::ofstream(home + "/outer.dat") << "call 'inner.dat'\ntitle 'outer went on'\n";
    }
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> "));
    t.type("call '" + home + "/outer.dat'\n");
    ASSERT_TRUE(t.expect("step 2000000000")) << t.seen(); // the echo of the script line
    usleep(300000);
    t.type("\x03");
    ASSERT_TRUE(t.expect("interrupted after")) << t.seen();
    ASSERT_TRUE(t.expect("inner.dat:5:1: interrupted: the script stops before this command")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("print info\n");
    ASSERT_TRUE(t.expect("title:      (none)")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}

TEST(Prompt, CtrlCStopsAScriptGivenOnTheCommandLine) {
    const std::string home = temp_home();
    std::ofstream(home + "/long.dat") << "poly brick 0 1 0 1 0 1\nprop mat=1 dens=1000\nset dt 1e-9\n"
                                         "step 2000000000\nprint info\n";
    const pid_t pid = fork();
    if (pid == 0) {
        const int devnull = open("/dev/null", O_WRONLY);
        dup2(devnull, 1);
        dup2(devnull, 2);
        execl(ODEC_BINARY, ODEC_BINARY, (home + "/long.dat").c_str(), static_cast<char*>(nullptr));
        _exit(127);
    }
    // Time for odec to start and take Ctrl-C as its own, then 10 s to end.
    usleep(static_cast<useconds_t>(500000 * odec::test::time_scale()));
    kill(pid, SIGINT);
    int status = 0;
    const auto end = std::chrono::steady_clock::now() + limit(10);
    bool ended = false;
    while (!(ended = waitpid(pid, &status, WNOHANG) == pid) && std::chrono::steady_clock::now() < end) usleep(100000);
    if (!ended) {
        kill(pid, SIGKILL); // not left stepping after the test
        waitpid(pid, nullptr, 0);
    }
    ASSERT_TRUE(ended && WIFEXITED(status)) << "odec did not end by itself after Ctrl-C";
    EXPECT_EQ(WEXITSTATUS(status), 130);
}

TEST(Prompt, CtrlCStopsMeshing) {
    // A million-zone 'gen' meshes for a minute: Ctrl-C stops it within moments, the block stays
    // rigid and unzoned, and the session goes on.
    const std::string home = temp_home();
    Terminal t(home);
    ASSERT_TRUE(t.expect("odec> "));
    t.type("poly brick 0 1 0 1 0 1\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("gen edge 0.012\n");
    usleep(1500000);
    const auto start = std::chrono::steady_clock::now();
    t.type("\x03");
    ASSERT_TRUE(t.expect("interrupted: the blocks were not zoned")) << t.seen();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 5.0 * odec::test::time_scale());
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("print info\n");
    ASSERT_TRUE(t.expect("blocks:     1")) << t.seen();
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    t.type("print zone\n");
    ASSERT_TRUE(t.expect("odec> ")) << t.seen();
    EXPECT_EQ(t.seen().find("zone 1 "), std::string::npos) << t.seen();
    t.type("quit\n");
    EXPECT_EQ(t.wait_exit(), 0) << t.seen();
}
