// frame_main: the C++ main of the frame harness sim/frame_tb.v under Verilator (no cocotb).
//
// Does what sim/frame_cocotb.py does under Icarus, with no Python in the simulator: clocks
// frame_tb, holds rst for 4 clocks, checks that texture_pipeline's outputs are reset (m_tvalid,
// m_tdata, m_tlast all 0 on the falling edge after), releases rst and clocks until the harness
// raises `done` (it has then written its colours, pass statistics and statistics files). Every
// per-pixel action is the harness's own, in Verilog. sim/frame_rtl.py (run_segments) starts it
// with the harness's plusargs and these:
//   +TIMEOUT=<clocks>   fail when `done` has not risen that many clocks after reset;
//   +RESET_AT=<clocks>  assert rst that many clocks after the first reset (the harness must be
//                       streaming, 0 < out_idx < +NPIXTOTAL), 3 clocks, then run to `done` again;
//   +NPIXTOTAL=<n>      the run's pixels (for the +RESET_AT check);
//   +WALL=<file>        write "stream_wall_us <us>": wall time from the last reset's release to done,
//                       "stream_cpu_us <us>", the process's CPU time over the same span, and
//                       "huge_text_bytes <n>", the bytes of code and tables in huge pages (huge_text);
//   +HOSTMEM=1 +PIXBIN=<file> +OUTBIN=<file>: the pixel words in binary (each PIX_W-bit word as
//                       ceil(PIX_W / 32) little-endian uint32, least significant first, +NPIXTOTAL
//                       words; model/hw/regmap.py pack_pixels_u32) loaded into the harness's pixel
//                       memory before reset, and its +NPIXTOTAL colours written back as uint32 after
//                       done (the harness then skips its $readmemh / $writememh of those two).
//   +HUGE_TEXT=0        leave the executable's code and tables in the file's pages (huge_text, below;
//                       sim/bench.py steps 16 measures it).
//   +EVAL_API=1         evaluate through Vframe_tb::eval() (with its bookkeeping), not the model's
//                       scheduler directly (below; sim/bench.py steps measures both).
//   +FALL_EVAL=1        evaluate the falling edge of every clock too (tick(), below; sim/bench.py
//                       steps 15 measures it).
//   +NBA_ONLY=0         run the scheduler's whole loop at every rising edge, not its NBA region alone
//                       when no input changed (tick(), below; sim/bench.py steps 17 measures it).
//   +COVERAGE=<file>    a build with Verilator's coverage (make coverage, COVERAGE=1): write the run's
//                       coverage points there when done.
// A failure prints one line "frame_tb: ERROR: ..." and exits with status 1 (the harness's own
// $display errors come first in the log; sim/frame_rtl.py shows the first).

#include <chrono>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <sys/mman.h>
#include <unistd.h>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "Vframe_tb.h"
#include "Vframe_tb___024root.h"
#include "verilated.h"
#if VM_COVERAGE
#include "verilated_cov.h"
#endif

namespace {

VerilatedContext* ctx;
Vframe_tb* top;

long plusarg(const char* name, long dflt) {
    const std::string key = std::string(name) + "=";
    const std::string m = ctx->commandArgsPlusMatch(key.c_str());
    if (m.empty()) return dflt;
    return std::strtol(m.c_str() + 1 + key.size(), nullptr, 10);
}

std::string plusarg_str(const char* name) {
    const std::string key = std::string(name) + "=";
    const std::string m = ctx->commandArgsPlusMatch(key.c_str());
    return m.empty() ? std::string() : m.substr(1 + key.size());
}

[[noreturn]] void fail(const std::string& why) {
    std::printf("frame_tb: ERROR: %s\n", why.c_str());
    std::fflush(stdout);
    top->final();
    std::exit(1);
}

// a pixel memory word from its uint32 words, least significant first
template <std::size_t N>
constexpr std::size_t words_of(const VlWide<N>*) { return N; }
constexpr std::size_t words_of(const QData*) { return 2; }
template <typename T>
constexpr std::size_t words_of(const T*) { return 1; }

template <std::size_t N>
void put(VlWide<N>& d, const uint32_t* s) { for (std::size_t i = 0; i < N; ++i) d[i] = s[i]; }
inline void put(QData& d, const uint32_t* s) { d = static_cast<QData>(s[0]) | static_cast<QData>(s[1]) << 32; }
template <typename T>
void put(T& d, const uint32_t* s) { d = static_cast<T>(s[0]); }

// The executable's own read-only mappings (its code and its constant tables, each a segment that
// starts on a 2 MiB boundary: the link's -z max-page-size=0x200000, sim/frame_rtl.py HUGE_ARGS) copied
// into anonymous memory in 2 MiB transparent huge pages and moved over the originals, at the same
// addresses with the same bytes. Mapped from the file, they sit in whatever 4 KiB page-cache pages
// the file was read into, and that placement set a build's speed: six copies of one `full`
// executable, run alternately, streamed a frame in 109-157 ms, each copy keeping its own time run
// after run, and one copy read in again (evicted from the page cache) took another; with the code
// in huge pages every copy took 111-122 ms (docs/simulation.md, stop 50). A segment not so aligned,
// one whose huge page would overlap another mapping, or a kernel that declines (no transparent
// huge pages: then 4 KiB pages, anonymous) stays as it was. +HUGE_TEXT=0 leaves them all. Returns
// the bytes moved; the run's +WALL file reports it (huge_text_bytes).
std::size_t huge_text() {
    constexpr std::uintptr_t HUGE = 2u << 20;
    std::ifstream maps("/proc/self/maps");
    std::string line, self;
    struct Map { std::uintptr_t lo, hi; std::string perm, path; };
    std::vector<Map> all;
    while (std::getline(maps, line)) {
        std::istringstream in(line);
        std::string range, perm, off, dev, inode, path;
        in >> range >> perm >> off >> dev >> inode;
        std::getline(in >> std::ws, path);  // the rest of the line: a path may hold spaces
        const auto dash = range.find('-');
        all.push_back({std::stoull(range.substr(0, dash), nullptr, 16), std::stoull(range.substr(dash + 1), nullptr, 16),
                       perm, path});
    }
    char exe[4096];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) return 0;
    self.assign(exe, static_cast<std::size_t>(n));
    std::size_t moved = 0;
    for (const Map& m : all) {
        if (m.path != self || m.perm[1] == 'w' || m.lo % HUGE) continue;
        const std::uintptr_t len = (m.hi - m.lo + HUGE - 1) / HUGE * HUGE;
        bool clear = true;  // nothing else mapped in the rest of the huge page
        for (const Map& o : all)
            if (&o != &m && o.lo < m.lo + len && o.hi > m.lo) clear = false;
        if (!clear) continue;
        void* raw = mmap(nullptr, len + HUGE, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (raw == MAP_FAILED) continue;
        const std::uintptr_t r = reinterpret_cast<std::uintptr_t>(raw);
        const std::uintptr_t a = (r + HUGE - 1) / HUGE * HUGE;  // its 2 MiB-aligned part
        if (a > r) munmap(raw, a - r);
        if (r + len + HUGE > a + len) munmap(reinterpret_cast<void*>(a + len), r + len + HUGE - (a + len));
        madvise(reinterpret_cast<void*>(a), len, MADV_HUGEPAGE);
        std::memcpy(reinterpret_cast<void*>(a), reinterpret_cast<const void*>(m.lo), m.hi - m.lo);
        const int prot = PROT_READ | (m.perm[2] == 'x' ? PROT_EXEC : 0);
        if (mprotect(reinterpret_cast<void*>(a), len, prot) != 0 ||
            mremap(reinterpret_cast<void*>(a), len, len, MREMAP_MAYMOVE | MREMAP_FIXED,
                   reinterpret_cast<void*>(m.lo)) == MAP_FAILED) {
            munmap(reinterpret_cast<void*>(a), len);
            continue;
        }
        moved += len;
    }
    return moved;
}

void load_pixels(const std::string& file, long npix) {
    auto& mem = top->rootp->frame_tb__DOT__pix_mem;
    using Word = std::remove_reference_t<decltype(mem[0])>;
    const std::size_t nw = words_of(static_cast<const Word*>(nullptr));
    std::vector<uint32_t> buf(static_cast<std::size_t>(npix) * nw);
    FILE* f = std::fopen(file.c_str(), "rb");
    if (!f) fail("cannot read +PIXBIN=" + file);
    const std::size_t got = std::fread(buf.data(), sizeof(uint32_t), buf.size(), f);
    std::fclose(f);
    if (got != buf.size() || npix > static_cast<long>(mem.size()))
        fail("+PIXBIN=" + file + ": " + std::to_string(got) + " words, expected " + std::to_string(buf.size()) +
             " (" + std::to_string(npix) + " pixels of " + std::to_string(nw) + " words, at most " +
             std::to_string(mem.size()) + " pixels)");
    for (long i = 0; i < npix; ++i) put(mem[i], &buf[static_cast<std::size_t>(i) * nw]);
}

void save_colours(const std::string& file, long npix) {
    auto& mem = top->rootp->frame_tb__DOT__out_mem;
    std::vector<uint32_t> buf(static_cast<std::size_t>(npix));
    for (long i = 0; i < npix; ++i) buf[static_cast<std::size_t>(i)] = mem[i];
    FILE* f = std::fopen(file.c_str(), "wb");
    if (!f || std::fwrite(buf.data(), sizeof(uint32_t), buf.size(), f) != buf.size()) fail("cannot write " + file);
    std::fclose(f);
}

}  // namespace

// The model's scheduler, as Verilator generates it (Vframe_tb___024root__0.cpp): what
// Vframe_tb::eval() runs between its once-a-call bookkeeping, VlDeleter::deleteAll (objects of
// SystemVerilog classes: the harness has none) and Verilated::endOfEval (messages posted by the
// worker threads of a --threads model: this one has none, so its $display's print at once).
// That bookkeeping takes two mutexes an eval, two evals a clock: 6 to 9% of a compact frame's
// time (perf, docs/simulation.md). tick() calls the scheduler itself; the first evaluation
// (initial blocks, settle) goes through eval().
void Vframe_tb___024root___eval(Vframe_tb___024root* vlSelf);
// The scheduler's NBA region alone (its dispatch on the triggers that fired): the one pass a rising
// edge of clk runs when no input of the model changed (tick(), below).
void Vframe_tb___024root___eval_nba(Vframe_tb___024root* vlSelf);

namespace {

// one clock: rising edge, then falling edge (inputs change between clocks, as cocotb's do on
// the falling edge). Every process of frame_tb and the design is clocked on the rising edge and
// nothing reads clk otherwise, so an evaluation at the falling edge has nothing to run: tick()
// skips it (a whole pass of the scheduler a clock, about 5 ns: 2.6% of a compact frame, whose
// pixels take five clocks; docs/simulation.md, stop 50) and only tells the scheduler that clk
// fell, by the trigger's previous value that eval() would have stored, so that the next rising
// edge is seen. +FALL_EVAL=1 evaluates it as Verilator's examples do (the same colours: tested,
// tests/test_frame_passes.py).
//
// The rising edge itself: the scheduler's loop (Vframe_tb___024root___eval) runs, a clock, its input
// phase (the logic that reads the model's inputs, clk and rst, recomputed because an input may have
// changed), its active phase (which finds the one trigger of the design, clk's rising edge) and then
// the NBA region (every clocked process, then the logic that reads their registers), and goes round
// once more to find nothing left to do. When rst has not changed since the last evaluation, only the
// NBA region has work: the input phase's logic is recomputed there from the registers it also reads,
// and clk feeds nothing but the trigger. tick() then runs that region alone, with the trigger set as
// the active phase would have set it (bit 0 of __VnbaTriggered), in a model whose one trigger is
// clk's rising edge: every RTL build's. A gate-level netlist's model can have others (Verilator's
// triggers on a wide register's changes, which it could not order statically; then clk's is not bit
// 0): sim/frame_rtl.py records each build's triggers and starts such a model with +NBA_ONLY=0. That
// is about 100 instructions a clock fewer, 3% of a compact clock's (cachegrind: docs/simulation.md,
// stop 51). A clock where rst changed (reset())
// goes through the whole loop. +NBA_ONLY=0 runs the whole loop every clock (the same colours and
// clocks: tests/test_frame_passes.py; sim/bench.py steps 17 measures it).
bool eval_api = false;  // +EVAL_API=1: every evaluation through Vframe_tb::eval() (sim/bench.py steps)
bool fall_eval = false;  // +FALL_EVAL=1: evaluate the falling edge too
bool nba_only = true;    // +NBA_ONLY=0 (or +EVAL_API=1, +FALL_EVAL=1): the scheduler's whole loop at every rising edge

inline void eval() {
    if (eval_api)
        top->eval();
    else
        Vframe_tb___024root___eval(top->rootp);
}

inline void tick() {
    Vframe_tb___024root* const r = top->rootp;
    top->clk = 1;
    if (nba_only && top->rst == r->frame_tb__DOT__rst) {
        r->frame_tb__DOT__clk = 1;  // what the input phase copies (left at 1, as the whole loop leaves it)
        r->__VnbaTriggered[0] = 1;  // clk's rising edge, as the active phase sets it
        Vframe_tb___024root___eval_nba(r);
        r->__VnbaTriggered[0] = 0;
    } else {
        eval();
    }
    ctx->timeInc(5);
    top->clk = 0;
    if (fall_eval)
        eval();
    else
        top->rootp->__Vtrigprevexpr___TOP__frame_tb__DOT__clk__0 = 0;
    ctx->timeInc(5);
    if (ctx->gotFinish()) fail("the harness stopped ($finish) before done");
}

void reset(int clocks, const char* what) {
    top->rst = 1;
    for (int i = 0; i < clocks; ++i) tick();
    Vframe_tb___024root* r = top->rootp;
    if (r->frame_tb__DOT__m_tvalid != 0) fail(std::string("m_axis_tvalid set during reset (") + what + ")");
    if (r->frame_tb__DOT__m_tdata != 0 || r->frame_tb__DOT__m_tlast != 0)
        fail(std::string("output registers not reset (") + what + ")");
    top->rst = 0;
}

}  // namespace

int main(int argc, char** argv) {
    ctx = new VerilatedContext;
    ctx->commandArgs(argc, argv);
    const std::size_t huge_bytes = plusarg("HUGE_TEXT", 1) != 0 ? huge_text() : 0;
    top = new Vframe_tb{ctx, "frame_tb"};
    const long timeout = plusarg("TIMEOUT", 10000000);
    const long reset_at = plusarg("RESET_AT", -1);
    const long npix = plusarg("NPIXTOTAL", 0);
    const std::string wall_file = plusarg_str("WALL");
    const bool hostmem = plusarg("HOSTMEM", 0) != 0;
    eval_api = plusarg("EVAL_API", 0) != 0;
    fall_eval = plusarg("FALL_EVAL", 0) != 0;
    nba_only = plusarg("NBA_ONLY", 1) != 0 && !eval_api && !fall_eval;  // either of those: the whole loop

    top->clk = 0;
    top->rst = 1;
    top->eval();  // initial blocks: plusargs, $readmemh
    if (ctx->gotFinish()) fail("the harness stopped ($finish) while loading");
    if (hostmem) load_pixels(plusarg_str("PIXBIN"), npix);
    reset(4, "right after reset");
    if (reset_at >= 0) {
        for (long i = 0; i < reset_at; ++i) tick();
        Vframe_tb___024root* r = top->rootp;
        const long out_idx = r->frame_tb__DOT__out_idx;
        if (r->frame_tb__DOT__state_reg != 1 || !(0 < out_idx && out_idx < npix))
            fail("reset not in the middle of the stream (state " + std::to_string(r->frame_tb__DOT__state_reg) +
                 ", " + std::to_string(out_idx) + " of " + std::to_string(npix) + " out)");
        std::printf("frame_tb: reset after %ld of %ld colours\n", out_idx, npix);
        reset(3, "right after the second reset");
    }
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();  // the process's CPU time: what the streaming costs, load aside
    long n = 0;
    while (!top->done) {
        if (n++ >= timeout)
            fail("harness not done after " + std::to_string(timeout) + " clocks: " +
                 std::to_string(top->rootp->frame_tb__DOT__out_idx) + " of " + std::to_string(npix) +
                 " colours received (state " + std::to_string(top->rootp->frame_tb__DOT__state_reg) +
                 "): pixels lost or the pipeline stopped");
        tick();
    }
    const double us = std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
    const double cpu_us = 1e6 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
    if (!wall_file.empty()) {
        FILE* f = std::fopen(wall_file.c_str(), "w");
        if (!f) fail("cannot write " + wall_file);
        std::fprintf(f, "stream_wall_us %ld\nstream_cpu_us %ld\nhuge_text_bytes %zu\n", static_cast<long>(us),
                     static_cast<long>(cpu_us), huge_bytes);
        std::fclose(f);
    }
    if (hostmem) save_colours(plusarg_str("OUTBIN"), npix);
    std::printf("frame_tb: %ld clocks after reset, %.3f s\n", n, us / 1e6);
    top->final();
#if VM_COVERAGE
    const std::string cov_file = plusarg_str("COVERAGE");
    if (!cov_file.empty()) ctx->coveragep()->write(cov_file.c_str());
#endif
    delete top;
    delete ctx;
    return 0;
}
