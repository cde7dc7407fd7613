// For the benchmarks that run another program beside odec (bench_stack, bench_ccx): find it on
// the PATH, run it in a directory and take its output, its exit status and the CPU seconds
// (user + system, all its threads and children) and wall seconds it took.
#pragma once

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

namespace odec_bench {

// The full path of an executable `name` found on the PATH, or "".
inline std::string find_program(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return "";
    std::string dirs = path;
    size_t start = 0;
    while (start <= dirs.size()) {
        size_t end = dirs.find(':', start);
        if (end == std::string::npos) end = dirs.size();
        const std::string dir = end > start ? dirs.substr(start, end - start) : ".";
        const std::string candidate = dir + "/" + name;
        if (access(candidate.c_str(), X_OK) == 0) return candidate;
        start = end + 1;
    }
    return "";
}

struct ChildRun {
    bool started = false;  // the program could be started
    int status = -1;       // its exit status (-1: killed by a signal or never started)
    std::string output;    // its standard output and standard error, interleaved
    double cpu = 0;        // s, user + system of the program (its threads and children included)
    double wall = 0;       // s
};

// A program started and not yet waited for (spawn_program).
struct Spawned {
    pid_t pid = -1;
    int fd = -1; // its standard output and error
    std::chrono::steady_clock::time_point w0;
};

// Starts `argv` (argv[0] a path) in directory `dir` with the extra environment `env`
// ("NAME=value"). (Call it while this process has one thread: the child allocates before it
// runs the program.)
inline Spawned spawn_program(const std::vector<std::string>& argv, const std::string& dir,
                             const std::vector<std::string>& env = {}) {
    Spawned sp;
    int fd[2];
    if (pipe(fd) != 0) return sp;
    sp.w0 = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid < 0) {
        close(fd[0]);
        close(fd[1]);
        return sp;
    }
    if (pid == 0) {
        close(fd[0]);
        dup2(fd[1], 1);
        dup2(fd[1], 2);
        close(fd[1]);
        if (!dir.empty() && chdir(dir.c_str()) != 0) _exit(127);
        for (const std::string& e : env) putenv(strdup(e.c_str()));
        std::vector<char*> args;
        for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
        args.push_back(nullptr);
        execv(args[0], args.data());
        _exit(127);
    }
    close(fd[1]);
    sp.pid = pid;
    sp.fd = fd[0];
    return sp;
}

// Reads a started program's output until it ends, and waits for it.
inline ChildRun collect_program(const Spawned& sp) {
    ChildRun r;
    if (sp.pid < 0) return r;
    char buf[65536];
    ssize_t n;
    while ((n = read(sp.fd, buf, sizeof buf)) > 0) r.output.append(buf, static_cast<size_t>(n));
    close(sp.fd);
    int status = 0;
    rusage ru{};
    wait4(sp.pid, &status, 0, &ru);
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - sp.w0).count();
    r.started = true;
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
            1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
    return r;
}

// Runs `argv` (argv[0] a path) in directory `dir` with the extra environment `env` ("NAME=value").
inline ChildRun run_program(const std::vector<std::string>& argv, const std::string& dir,
                            const std::vector<std::string>& env = {}) {
    return collect_program(spawn_program(argv, dir, env));
}

// User + system CPU seconds of this process so far (all its threads).
inline double process_cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
           1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

} // namespace odec_bench
