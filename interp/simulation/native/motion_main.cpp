// SPDX-License-Identifier: Apache-2.0
// Native Verilator harness for rtl/motion_top.v (no cocotb, no Python per cycle).
//
//   motion_sim --commands FILE --steps FILE --result FILE --max-cycles N
//              --timing PULSE_WIDTH,SETUP,HOLD [--vcd FILE] [--progress-log2 K]
//
// Command file: one command per line, 10 decimal integers
// "kind plane feed x y z i j k l" (blank lines skipped).  The harness drives
// motion_top as interp/simulation/motion_driver.py does under cocotb: inputs
// change while clk is low, outputs are sampled after each rising edge; rst for
// two rising edges, then the first cycle counts 1.  A command is pushed
// (cmd_valid) in every cycle whose previous sample showed cmd_full low, hold
// (feed hold) stays 0.  It stops when every command is pushed and busy is low,
// or after --max-cycles cycles ("stopped": true in the result).
//
// Steps CSV: "cycle,dx,dy,dz", one row per cycle with a rising edge on any
// step output (d = -1 if dir is set, 1 if not, 0 without a rising edge).
// Result (JSON): cycles, position, errors [[cycle, code]], events
// [[cycle, code, value]], steps (rows), stopped, pushed, dispatched, commands.
// Progress on stdout every 2^K cycles: "progress <cycle> <steps> <dispatched>".
// Bad input: one line on stderr, exit status 2.
//
// Compile-time settings (harness_config.h, written by interp/simulation/native/build.py): MT_W,
// MT_FEED_W, MT_POS_W, MT_TW (parameter widths, each <= 64), HAS_PLANE,
// HAS_EVENTS (the ports exist), TRACE (VCD support), QUIET_SKIP with MT_AW
// (feed_rate's accumulator u_feed.acc and feed_q are in the model, <= 64
// bits) and, when found, MT_SINCE_W, MT_COUNT_W (step_dir's since_fall and
// count) and MT_DWELL_W (motion_top's dwell_q).
//
// Quiet stretches (QUIET_SKIP; off with --exact 1 or --vcd): at a low feed the
// drive waits thousands of cycles between steps, and in those cycles only
// counters change.  When, some cycles after the last step, push, error or
// event, every member of Verilator's model (root object) is bit-identical to
// its value 6 cycles before (PERIOD: with the step buffer empty the STOP logic
// cycles through 3 states) except these counters, and each of them moved as its
// rule says every cycle, the following periods are the same up to the first cycle in which
// a counter reaches the value the RTL acts on; the harness moves the counters
// on to a cycle before that and counts the cycles in between.  The rules (the
// RTL as it is; a change there needs a change here, and the tests compare
// with --exact and with Icarus):
//   feed_rate acc     grows by feed_q while negative (tick low), else holds;
//                     read only through its sign (tick): stop before it turns >= 0
//   step_dir since_fall  +1 per cycle, saturating; read through `held`
//                     (since_fall + 1 >= hold) and saturation: stop before held
//   step_dir count    -1 per cycle in SETUP/PULSE; acts at 1: stop before
//   motion_top dwell_q   -1 per cycle in DWELL; acts at 0: stop before
// Same files, same results; the cycle each thing happens in is unchanged.
#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "harness_config.h"     // generated in the build folder
#include "Vmotion_top.h"
#include "verilated.h"
#ifdef QUIET_SKIP
#include "Vmotion_top___024root.h"
#endif
#ifdef TRACE
#include "verilated_vcd_c.h"
#endif

#if MT_W > 64 || MT_FEED_W > 64 || MT_POS_W > 64 || MT_TW > 64
#error "the native harness supports port widths up to 64 bits"
#endif

namespace {

constexpr int NFIELDS = 10;
const char* const FIELD_NAMES[NFIELDS] = {"kind", "plane", "feed", "x", "y", "z", "i", "j", "k", "l"};

struct Command {
    uint64_t field[NFIELDS];    // each already truncated to its port width
};

uint64_t mask(int bits) { return bits >= 64 ? ~0ULL : (1ULL << bits) - 1; }

int64_t sign_extend(uint64_t value, int bits) {
    if (bits >= 64) return static_cast<int64_t>(value);
    const uint64_t m = 1ULL << (bits - 1);
    value &= mask(bits);
    return static_cast<int64_t>((value ^ m) - m);
}

[[noreturn]] void fail(const std::string& text) {
    std::fprintf(stderr, "%s\n", text.c_str());
    std::exit(2);
}

std::string shown(const char* begin, const char* end) {
    std::string text(begin, end);
    if (text.size() > 60) text = text.substr(0, 57) + "...";
    return text;
}

// Reads the whole command file; any bad line ends the run with one message.
std::vector<Command> read_commands(const char* path) {
    FILE* f = std::fopen(path, "rb");
    if (!f) fail(std::string("cannot read the command file ") + path + ": " + std::strerror(errno));
    std::string text;
    char chunk[1 << 16];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) text.append(chunk, n);
    std::fclose(f);

    // allowed ranges: kind 3 bits, plane 2 bits, feed unsigned FEED_W bits,
    // x .. l: signed W bits, or unsigned W bits (a dwell's cycle count)
    const int64_t lo_w = MT_W >= 64 ? INT64_MIN : -(int64_t(1) << (MT_W - 1));
    const uint64_t hi_w = mask(MT_W);
    std::vector<Command> commands;
    const char* p = text.c_str();
    const char* const end = p + text.size();
    for (long line = 1; p < end; ++line) {
        const char* eol = static_cast<const char*>(std::memchr(p, '\n', end - p));
        if (!eol) eol = end;
        const char* q = p;
        while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
        if (q == eol) {                                    // blank line
            p = eol + 1;
            continue;
        }
        Command cmd{};
        const std::string where = std::string(path) + " line " + std::to_string(line) + ": ";
        for (int k = 0; k < NFIELDS; ++k) {
            while (q < eol && (*q == ' ' || *q == '\t')) ++q;
            const char* start = q;
            if (q < eol && (*q == '-' || *q == '+')) ++q;
            const char* digits = q;
            while (q < eol && *q >= '0' && *q <= '9') ++q;
            if (q == digits || (q < eol && *q != ' ' && *q != '\t' && *q != '\r'))
                fail(where + "want 10 integers \"kind plane feed x y z i j k l\", got \"" +
                     shown(p, eol) + "\"");
            const std::string word(start, q);
            errno = 0;
            bool ok;
            uint64_t value;
            if (word[0] == '-') {
                const long long v = std::strtoll(word.c_str(), nullptr, 10);
                ok = errno == 0 && k >= 3 && v >= lo_w;
                value = static_cast<uint64_t>(v);
            } else {
                const unsigned long long v = std::strtoull(word.c_str(), nullptr, 10);
                const uint64_t hi = k == 0 ? 7 : k == 1 ? 3 : k == 2 ? mask(MT_FEED_W) : hi_w;
                ok = errno == 0 && v <= hi;
                value = v;
            }
            if (!ok)
                fail(where + FIELD_NAMES[k] + " " + word + " is out of range (kind 0 .. 7, plane 0 .. 3, feed 0 .. 2^" +
                     std::to_string(MT_FEED_W) + " - 1, x .. l " + std::to_string(MT_W) + "-bit integers)");
            const int bits = k == 0 ? 3 : k == 1 ? 2 : k == 2 ? MT_FEED_W : MT_W;
            cmd.field[k] = value & mask(bits);
        }
        while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
        if (q != eol)
            fail(where + "want 10 integers \"kind plane feed x y z i j k l\", got \"" + shown(p, eol) + "\"");
#ifndef HAS_PLANE
        if (cmd.field[1] != 0) fail(where + "plane " + std::to_string(cmd.field[1]) +
                                    ", but this motion_top has no cmd_plane port (use 0)");
#endif
        commands.push_back(cmd);
        p = eol + 1;
    }
    return commands;
}

// Buffered writer for the steps CSV (millions of rows).
class Writer {
  public:
    explicit Writer(const char* path) : file_(std::fopen(path, "wb")), path_(path) {
        if (!file_) fail(std::string("cannot write ") + path + ": " + std::strerror(errno));
        buffer_.reserve(kSize + 64);
    }
    ~Writer() { close(); }
    void text(const char* s) {
        buffer_.append(s);
        flush_if_full();
    }
    void row(uint64_t cycle, int dx, int dy, int dz) {
        char tmp[80];
        char* e = tmp + sizeof tmp;
        char* b = e;
        *--b = '\n';
        for (int d : {dz, dy, dx}) {
            *--b = d ? '1' : '0';
            if (d < 0) *--b = '-';
            *--b = ',';
        }
        do {
            *--b = char('0' + cycle % 10);
            cycle /= 10;
        } while (cycle);
        buffer_.append(b, e - b);
        flush_if_full();
    }
    void close() {
        if (!file_) return;
        write();
        if (std::fclose(file_) != 0) fail(std::string("cannot write ") + path_ + ": " + std::strerror(errno));
        file_ = nullptr;
    }

  private:
    static constexpr size_t kSize = 1 << 20;
    void flush_if_full() {
        if (buffer_.size() >= kSize) write();
    }
    void write() {
        if (!buffer_.empty() && std::fwrite(buffer_.data(), 1, buffer_.size(), file_) != buffer_.size())
            fail(std::string("cannot write ") + path_ + ": " + std::strerror(errno));
        buffer_.clear();
    }
    FILE* file_;
    std::string path_;
    std::string buffer_;
};

uint64_t number(const char* name, const char* text) {
    char* end;
    errno = 0;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (errno || *end || !*text || text[0] == '-') fail(std::string("bad ") + name + " " + text);
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    const char *commands_path = nullptr, *steps_path = nullptr, *result_path = nullptr, *vcd_path = nullptr;
    uint64_t max_cycles = 0, timing[3] = {1, 0, 0};
    int progress_log2 = 22;
    bool exact = false;
    for (int a = 1; a < argc; ++a) {
        const std::string opt = argv[a];
        if (a + 1 >= argc) fail("option " + opt + " needs a value");
        const char* value = argv[++a];
        if (opt == "--commands") commands_path = value;
        else if (opt == "--steps") steps_path = value;
        else if (opt == "--result") result_path = value;
        else if (opt == "--vcd") vcd_path = value;
    else if (opt == "--exact") exact = number("--exact", value) != 0;
        else if (opt == "--max-cycles") max_cycles = number("--max-cycles", value);
        else if (opt == "--progress-log2") progress_log2 = int(number("--progress-log2", value));
        else if (opt == "--timing") {
            std::string t = value;
            for (int k = 0; k < 3; ++k) {
                const size_t comma = t.find(',');
                if ((comma == std::string::npos) != (k == 2)) fail("--timing wants PULSE_WIDTH,SETUP,HOLD");
                timing[k] = number("--timing", t.substr(0, comma).c_str());
                if (timing[k] > mask(MT_TW)) fail("--timing: value above 2^TW - 1");
                t = comma == std::string::npos ? "" : t.substr(comma + 1);
            }
        } else fail("unknown option " + opt);
    }
    if (!commands_path || !steps_path || !result_path) fail("need --commands, --steps and --result");
#ifndef TRACE
    if (vcd_path) fail("this build has no VCD support (build it with trace)");
#endif
    if (progress_log2 < 1 || progress_log2 > 62) fail("--progress-log2 must be 1 .. 62");

    const std::vector<Command> commands = read_commands(commands_path);
    Writer steps(steps_path);
    steps.text("cycle,dx,dy,dz\n");

    auto context = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vmotion_top>(context.get(), "motion_top");
#ifdef TRACE
    std::unique_ptr<VerilatedVcdC> vcd;
    if (vcd_path) {
        context->traceEverOn(true);
        vcd = std::make_unique<VerilatedVcdC>();
        top->trace(vcd.get(), 99);
        vcd->open(vcd_path);
    }
    uint64_t time_ns = 0;
    auto eval = [&] {
        top->eval();
        if (vcd) vcd->dump(time_ns);
        time_ns += 5;                       // 10 ns clock, as the cocotb benches
    };
#else
    auto eval = [&] { top->eval(); };
#endif

    // reset: idle inputs, rst for two rising edges
    top->clk = 0;
    top->rst = 1;
    top->cmd_valid = 0;
    top->hold = 0;
    top->cmd_kind = 0;
#ifdef HAS_PLANE
    top->cmd_plane = 0;
#endif
    top->cmd_feed = 0;
    top->cmd_x = top->cmd_y = top->cmd_z = top->cmd_i = top->cmd_j = top->cmd_k = top->cmd_l = 0;
    top->pulse_width = timing[0];
    top->setup = timing[1];
    top->hold_time = timing[2];
    eval();
    for (int k = 0; k < 2; ++k) {
        top->clk = 1;
        eval();
        top->clk = 0;
        eval();
    }
    top->rst = 0;

    std::vector<std::pair<uint64_t, unsigned>> errors;
    struct Event {
        uint64_t cycle;
        unsigned code;
        int64_t value;
    };
    std::vector<Event> events;
    const size_t total = commands.size();
    size_t next = 0;
    uint64_t cycle = 0, rows = 0;
    unsigned prev_step = 0;
    bool stopped = false;
    const uint64_t progress_mask = (1ULL << progress_log2) - 1;
#ifdef QUIET_SKIP
    auto* root = top->rootp;
    const bool skip = !exact && !vcd_path;
    std::vector<unsigned char> snapshot(sizeof *root);
    // a counter of the model: where it is, its width, its value at the snapshot
    struct Counter {
        void* at;
        size_t size;
        int bits;
        uint64_t before;
        uint64_t get() const {
            uint64_t v = 0;
            std::memcpy(&v, at, size);      // little-endian: the low bytes of v
            return v & mask(bits);
        }
        void set(uint64_t v) { std::memcpy(at, &v, size); }
        size_t offset(const void* base) const {
            return static_cast<const unsigned char*>(at) - static_cast<const unsigned char*>(base);
        }
    };
#define MT_COUNTER(member, width) Counter{&root->member, sizeof root->member, width, 0}
    Counter acc = MT_COUNTER(motion_top__DOT__u_feed__DOT__acc, MT_AW);
#ifdef MT_SINCE_W
    Counter since = MT_COUNTER(motion_top__DOT__u_out__DOT__since_fall, MT_SINCE_W);
#endif
#ifdef MT_COUNT_W
    Counter count = MT_COUNTER(motion_top__DOT__u_out__DOT__count, MT_COUNT_W);
#endif
#ifdef MT_DWELL_W
    Counter dwell = MT_COUNTER(motion_top__DOT__dwell_q, MT_DWELL_W);
#endif
    Counter* counters[] = {&acc,
#ifdef MT_SINCE_W
                           &since,
#endif
#ifdef MT_COUNT_W
                           &count,
#endif
#ifdef MT_DWELL_W
                           &dwell,
#endif
    };
    // The state other than the counters may repeat with a period instead of standing
    // still: with the step buffer empty (a dwell, the drain before an event) STOP and the
    // ticks in flight cycle through 3 states.  PERIOD is a multiple of every such period;
    // the snapshot is compared with the state PERIOD cycles later and jumps are whole periods.
    constexpr uint64_t PERIOD = 6;
    uint64_t calm = 0, check_at = 8, skipped = 0;
#else
    (void)exact;
    const uint64_t skipped = 0;
#endif

    for (;;) {
        // inputs for the next rising edge, from the last sample (clk is low)
        const bool push = next < total && !top->cmd_full;
        if (push) {
            const uint64_t* f = commands[next++].field;
            top->cmd_kind = f[0];
#ifdef HAS_PLANE
            top->cmd_plane = f[1];
#endif
            top->cmd_feed = f[2];
            top->cmd_x = f[3];
            top->cmd_y = f[4];
            top->cmd_z = f[5];
            top->cmd_i = f[6];
            top->cmd_j = f[7];
            top->cmd_k = f[8];
            top->cmd_l = f[9];
            top->cmd_valid = 1;
        } else {
            top->cmd_valid = 0;
        }
        top->clk = 0;
        eval();
        top->clk = 1;
        eval();
        ++cycle;

        const unsigned step = top->step_x | top->step_y << 1 | top->step_z << 2;
        const unsigned rise = step & ~prev_step;
        prev_step = step;
        if (rise) {
            steps.row(cycle, rise & 1 ? (top->dir_x ? -1 : 1) : 0, rise & 2 ? (top->dir_y ? -1 : 1) : 0,
                      rise & 4 ? (top->dir_z ? -1 : 1) : 0);
            ++rows;
        }
        if (top->error) errors.emplace_back(cycle, unsigned(top->error_code));
#ifdef HAS_EVENTS
        if (top->event_valid)
            events.push_back({cycle, unsigned(top->event_code), sign_extend(top->event_value, MT_W)});
#endif
        if ((cycle & progress_mask) == 0) {
            std::printf("progress %" PRIu64 " %" PRIu64 " %zu\n", cycle, rows, next - size_t(top->queue_level));
            std::fflush(stdout);
        }
        if (next == total && !push && !top->busy) break;
        if (cycle >= max_cycles) {
            stopped = true;
            break;
        }
#ifdef QUIET_SKIP
        if (skip) {
            bool active = push || rise || top->error;
#ifdef HAS_EVENTS
            active = active || top->event_valid;
#endif
            if (active) {
                calm = 0;
            } else if (++calm == check_at) {
                std::memcpy(snapshot.data(), root, sizeof *root);
                for (Counter* c : counters) c->before = c->get();
            } else if (calm == check_at + PERIOD) {
                calm = 0;
                // the largest number of cycles every counter allows (0: none)
                uint64_t jump = max_cycles - cycle - 1;       // cycle < max_cycles here
                const int64_t a = sign_extend(acc.get(), MT_AW), a0 = sign_extend(acc.before, MT_AW);
                const uint64_t feed = root->motion_top__DOT__u_feed__DOT__feed_q;
                if (a < 0 && a0 < 0 && (uint64_t(a - a0) & mask(MT_AW)) == ((PERIOD * feed) & mask(MT_AW))) {
                    if (feed) jump = std::min(jump, (uint64_t(-a) + feed - 1) / feed - 1);
                } else if (!(a >= 0 && a == a0)) {
                    jump = 0;
                }
#ifdef MT_SINCE_W
                const uint64_t s_now = since.get(), s_top = mask(MT_SINCE_W);
                if (s_now == s_top ? since.before != s_top : s_now != since.before + PERIOD) jump = 0;
                const uint64_t hold_time = top->hold_time;
                if (s_now != s_top && s_now + 1 < hold_time) jump = std::min(jump, hold_time - s_now - 2);
#endif
#ifdef MT_COUNT_W
                const uint64_t c_now = count.get();
                if (c_now + PERIOD == count.before) jump = c_now >= 2 ? std::min(jump, c_now - 2) : 0;
                else if (c_now != count.before) jump = 0;
#endif
#ifdef MT_DWELL_W
                const uint64_t d_now = dwell.get();
                if (d_now + PERIOD == dwell.before) jump = d_now >= 1 ? std::min(jump, d_now - 1) : 0;
                else if (d_now != dwell.before) jump = 0;
#endif
                jump -= jump % PERIOD;          // whole periods: the rest of the state repeats
                if (jump) {
                    for (Counter* c : counters) {
                        const uint64_t v = c->get();
                        std::memcpy(snapshot.data() + c->offset(root), &v, c->size);
                    }
                    if (std::memcmp(snapshot.data(), root, sizeof *root) != 0) jump = 0;
                }
                if (jump) {
                    const uint64_t before = cycle;
                    if (a < 0) acc.set(uint64_t(a + int64_t(jump * feed)) & mask(MT_AW));
#ifdef MT_SINCE_W
                    if (s_now != s_top) since.set(jump >= s_top - s_now ? s_top : s_now + jump);
#endif
#ifdef MT_COUNT_W
                    if (c_now + PERIOD == count.before) count.set(c_now - jump);
#endif
#ifdef MT_DWELL_W
                    if (d_now + PERIOD == dwell.before) dwell.set(d_now - jump);
#endif
                    cycle += jump;
                    skipped += jump;
                    if ((before >> progress_log2) != (cycle >> progress_log2)) {
                        std::printf("progress %" PRIu64 " %" PRIu64 " %zu\n", cycle, rows,
                                    next - size_t(top->queue_level));
                        std::fflush(stdout);
                    }
                    check_at = 8;
                } else if (check_at < 4096) {
                    check_at *= 2;
                }
            }
        }
#endif
    }
    top->clk = 0;
    eval();                                 // the last falling edge (waveform)
    steps.close();
#ifdef TRACE
    if (vcd) vcd->close();
#endif

    FILE* out = std::fopen(result_path, "w");
    if (!out) fail(std::string("cannot write ") + result_path + ": " + std::strerror(errno));
    std::fprintf(out, "{\"cycles\": %" PRIu64 ", \"position\": [%" PRId64 ", %" PRId64 ", %" PRId64 "], ", cycle,
                 sign_extend(top->pos_x, MT_POS_W), sign_extend(top->pos_y, MT_POS_W),
                 sign_extend(top->pos_z, MT_POS_W));
    std::fprintf(out, "\"errors\": [");
    for (size_t k = 0; k < errors.size(); ++k)
        std::fprintf(out, "%s[%" PRIu64 ", %u]", k ? ", " : "", errors[k].first, errors[k].second);
    std::fprintf(out, "], \"events\": [");
    for (size_t k = 0; k < events.size(); ++k)
        std::fprintf(out, "%s[%" PRIu64 ", %u, %" PRId64 "]", k ? ", " : "", events[k].cycle, events[k].code,
                     events[k].value);
    std::fprintf(out, "], \"steps\": %" PRIu64 ", \"stopped\": %s, \"pushed\": %zu, \"dispatched\": %zu, "
                 "\"commands\": %zu, \"skipped\": %" PRIu64 "}\n", rows, stopped ? "true" : "false", next,
                 next - size_t(top->queue_level), total, uint64_t(skipped));
    if (std::fclose(out) != 0) fail(std::string("cannot write ") + result_path);
    top->final();
    return 0;
}
