// A libFuzzer-compatible driver for builds without libFuzzer (GCC, the ci and asan builds):
// runs every input of the corpus once, then a fixed number of seeded mutations of them
// (byte flips, inserts, deletions, repeats, cuts, dictionary tokens, splices), each under a
// time limit. On a crash, a sanitizer report or a hang the input is written to
// `fuzz-failure-<target>` in the working folder and the driver exits non-zero.
//   fuzz_TARGET [--runs N] [--seed S] [--dict FILE] [--timeout SECONDS] [--ext .plant] FILE_OR_FOLDER...
// (--ext: only the folders' files with that ending)
#include <algorithm>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

const std::string* g_current = nullptr;
char g_failure_path[512] = "fuzz-failure";

// Async-signal-safe: writes the input being run, then lets the signal end the process.
void on_signal(int sig) {
    if (g_current) {
        const int fd = ::open(g_failure_path, O_CREAT | O_WRONLY | O_TRUNC, 0644);
        if (fd >= 0) {
            ssize_t n = ::write(fd, g_current->data(), g_current->size());
            (void)n;
            ::close(fd);
        }
        const char* what = sig == SIGALRM ? "fuzz: an input took longer than the time limit (a hang); written to "
                                          : "fuzz: an input crashed; written to ";
        ssize_t n = ::write(2, what, std::strlen(what));
        n = ::write(2, g_failure_path, std::strlen(g_failure_path));
        n = ::write(2, "\n", 1);
        (void)n;
    }
    if (sig == SIGALRM) ::_exit(2);
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

std::string read_file(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// libFuzzer's dictionary format: one "token" per line (name="..." allowed), \xNN escapes.
std::vector<std::string> read_dict(const std::string& path) {
    std::vector<std::string> out;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        const size_t a = line.find('"'), b = line.rfind('"');
        if (line.empty() || line[0] == '#' || a == std::string::npos || b <= a) continue;
        std::string t;
        for (size_t i = a + 1; i < b; ++i) {
            if (line[i] == '\\' && i + 1 < b) {
                if (line[i + 1] == 'x' && i + 3 < b) {
                    t += char(std::stoi(line.substr(i + 2, 2), nullptr, 16));
                    i += 3;
                } else t += line[++i];
            } else t += line[i];
        }
        out.push_back(t);
    }
    return out;
}

std::string mutate(std::string s, const std::vector<std::string>& corpus, const std::vector<std::string>& dict,
                   std::mt19937_64& rnd) {
    auto pick = [&](size_t n) { return n ? size_t(rnd() % n) : 0; };
    const int edits = 1 + int(pick(4));
    for (int e = 0; e < edits; ++e) {
        const size_t at = pick(s.size() + 1);
        switch (pick(8)) {
        case 0:  // flip a bit
            if (!s.empty()) s[pick(s.size())] ^= char(1u << pick(8));
            break;
        case 1: s.insert(at, 1, char(pick(256))); break;  // a random byte
        case 2: s.erase(at, 1 + pick(16)); break;         // delete a run
        case 3:                                            // repeat a run
            if (at < s.size()) s.insert(at, s.substr(at, 1 + pick(32)));
            break;
        case 4: s.resize(at); break;  // cut short
        case 5:
        case 6:  // a token of the language
            if (!dict.empty()) s.insert(at, dict[pick(dict.size())]);
            break;
        default: {  // splice in a piece of another input
            const std::string& o = corpus[pick(corpus.size())];
            const size_t from = pick(o.size() + 1);
            s.insert(at, o.substr(from, 1 + pick(256)));
        }
        }
    }
    return s;
}

}  // namespace

int main(int argc, char** argv) {
    long runs = 500, timeout = 20;
    uint64_t seed = 20261124;
    std::string dict_path, ext;
    std::vector<std::filesystem::path> inputs;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "fuzz: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--runs") runs = std::stol(value());
        else if (a == "--seed") seed = std::stoull(value());
        else if (a == "--dict") dict_path = value();
        else if (a == "--timeout") timeout = std::stol(value());
        else if (a == "--ext") ext = value();
        else inputs.emplace_back(a);
    }
    const std::string target = std::filesystem::path(argv[0]).filename().string();
    std::snprintf(g_failure_path, sizeof g_failure_path, "fuzz-failure-%s", target.c_str());
    std::vector<std::filesystem::path> files;
    for (const auto& p : inputs) {
        if (std::filesystem::is_directory(p)) {
            for (const auto& e : std::filesystem::recursive_directory_iterator(p))
                if (e.is_regular_file() && (ext.empty() || e.path().extension() == ext)) files.push_back(e.path());
        } else if (std::filesystem::is_regular_file(p)) files.push_back(p);
        else {
            std::fprintf(stderr, "fuzz: %s: no such file or folder\n", p.c_str());
            return 2;
        }
    }
    std::sort(files.begin(), files.end());
    std::vector<std::string> corpus;
    for (const auto& f : files) corpus.push_back(read_file(f));
    if (corpus.empty()) corpus.emplace_back();
    const std::vector<std::string> dict = dict_path.empty() ? std::vector<std::string>{} : read_dict(dict_path);
    for (int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGALRM}) std::signal(sig, on_signal);

    auto run = [&](const std::string& input) {
        g_current = &input;
        ::alarm(unsigned(timeout));
        LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(input.data()), input.size());
        ::alarm(0);
        g_current = nullptr;
    };
    for (const std::string& c : corpus) run(c);
    std::mt19937_64 rnd(seed);
    for (long i = 0; i < runs; ++i) run(mutate(corpus[size_t(rnd() % corpus.size())], corpus, dict, rnd));
    std::printf("%s: %zu corpus inputs and %ld mutations (seed %llu, %zu dictionary tokens): no crash, no hang\n",
                target.c_str(), corpus.size(), runs, static_cast<unsigned long long>(seed), dict.size());
    return 0;
}
