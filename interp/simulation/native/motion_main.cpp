// SPDX-License-Identifier: Apache-2.0
// Native Verilator harness for rtl/motion_top.v (no cocotb, no Python per cycle).
//
//   motion_sim --commands FILE --steps FILE --result FILE --max-cycles N
//              --timing PULSE_WIDTH,SETUP,HOLD [--settings QUANTUM,BLOCK_SHIFT,JERK_SHIFT,OVERRIDE]
//              [--controls FILE] [--vcd FILE] [--progress-log2 K] [--push-interval K]
//
// Command file: one command per line, 16 decimal integers
// "kind plane feed x y z i j k l limit exit rate cost length budget" (blank
// lines skipped; length and budget may be wider than 64 bits).  The harness drives
// motion_top as interp/simulation/motion_driver.py does under cocotb: inputs
// change while clk is low, outputs are sampled after each rising edge; rst for
// two rising edges, then the first cycle counts 1.  A command is pushed
// (cmd_valid) in every cycle whose previous sample showed cmd_full low and that is at
// least --push-interval cycles (default 1) after the previous push: the controller's
// record unpacker hands a record on every RECORD_BYTES + 8 + DERIVE_CLOCKS clocks at
// most (compact records, DERIVE_CLOCKS = 4 W + FRAC + 7 + max(W, 64 + max(FEED_W,
// PF + 1)) + ZW + 15; RECORD_BYTES + 1 plain ones).
// Settings: speed_quantum, block_shift, jerk_shift, override (default 1,0,0,100).
// Controls file: lines "CYCLE hold|resume|override VALUE", cycles not decreasing;
// each is applied after the sample of that cycle (cycle 0: before the first edge),
// so the rising edge that ends cycle CYCLE + 1 sees it.  hold_stops in the result:
// [cycle of the hold, first cycle with `stopped` high (null if resumed before),
// step rows between the two].  It stops when every command is pushed, busy is low
// and no control is left, or after --max-cycles cycles ("stopped": true).
//
// Steps CSV: "cycle,dx,dy,dz", one row per cycle with a rising edge on any
// step output (d = -1 if dir is set, 1 if not, 0 without a rising edge).
// Result (JSON): cycles, position, errors [[cycle, code]], events
// [[cycle, code, value]], steps (rows), stopped, pushed, dispatched, commands.
// Progress on stdout every 2^K cycles: "progress <cycle> <steps> <dispatched>".
// Bad input: one line on stderr, exit status 2.
//
// Compile-time settings (harness_config.h, written by interp/simulation/native/build.py): MT_W,
// MT_FEED_W, MT_POS_W, MT_TW (parameter widths, each <= 64), MT_NW, MT_PF, MT_LEN_W,
// MT_ZW (the profile fields' widths; length and budget any width), HAS_PLANE,
// HAS_EVENTS (the ports exist), TRACE (VCD support), QUIET_SKIP (the members below
// were found in Verilator's model, each <= 64 bits): MT_ACC_W (speed_ramp's DDA phase
// acc), MT_WA_W (jerk_filter's write_address), MT_SINCE_W, MT_COUNT_W (step_dir's
// since_fall and count), MT_DWELL_W (motion_top's dwell_q).
//
// Quiet stretches (QUIET_SKIP; off with --exact 1 or --vcd): a long dwell, or a hold
// that has stopped the machine, runs millions of cycles in which only counters
// change.  Skipped ONLY while the path is at rest: speed 0, the ramp's n = 0 and no
// segment in progress, the S-curve filter's sum and difference 0 (so no code left in
// its delay line will change it: it is empty), the pacer then gets 0 every clock.
// (Stretches between steps at a low speed are not skipped: the ramp's remaining
// distance, budget and the pacer's phase are wider than 64 bits at the CLI build.)
// When, some cycles after the last step, push, error, event or control, every member
// of Verilator's model (root object) is bit-identical to its value PERIOD cycles
// before (PERIOD = 18 << block_shift: the STOP logic of an empty step buffer cycles
// through 3 states, the ramp's override product is recomputed every 9 clocks, its
// block counter every 2^block_shift) except these counters, and each moved as its rule
// says, the following periods are the same up to the first cycle in which a counter
// reaches the value the RTL acts on; the harness moves the counters on to a cycle
// before that and counts the cycles in between.  The rules (the RTL as it is; a change
// there needs a change here, and the tests compare with --exact and with Icarus):
//   speed_ramp acc      += rate per block, modulo 2^PF; at rest (n = 0, no segment,
//                       p n = 0) its overflow changes nothing
//   jerk_filter write_address  +1 per block, modulo 2^MW; the filter empty, every code
//                       read and written is 0
//                       (these two are not moved: values Verilator derives from them are
//                       members too, so a jump is a whole number of the periods after which
//                       both are back: 2^PF / gcd(their step a period, 2^PF) periods; with
//                       the rate a multiple of 2^PF / 2 that is one, else it can be long)
//   step_dir since_fall  +1 per cycle, saturating; read through `held`
//                       (since_fall + 1 >= hold) and saturation: stop before held
//   step_dir count      -1 per cycle in SETUP/PULSE; acts at 1: stop before
//   motion_top dwell_q  -1 per cycle in DWELL; acts at 0: stop before
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

constexpr int NFIELDS = 16;
const char* const FIELD_NAMES[NFIELDS] = {"kind", "plane", "feed", "x", "y", "z", "i", "j", "k", "l",
                                          "limit", "exit", "rate", "cost", "length", "budget"};
constexpr int BIG_WORDS = 8;    // fields up to 256 bits
const char* const USAGE = "want 16 integers \"kind plane feed x y z i j k l limit exit rate cost length budget\"";

uint64_t mask(int bits) { return bits >= 64 ? ~0ULL : (1ULL << bits) - 1; }

// A field's value: little-endian 32-bit words, already truncated to its port width.
struct Big {
    uint32_t w[BIG_WORDS] = {};
    uint64_t low() const { return w[0] | uint64_t(w[1]) << 32; }
    bool zero() const {
        for (uint32_t x : w) if (x) return false;
        return true;
    }
    // *10 + digit; false on overflow of 256 bits
    bool push_digit(unsigned digit) {
        uint64_t carry = digit;
        for (uint32_t& x : w) {
            const uint64_t v = uint64_t(x) * 10 + carry;
            x = uint32_t(v);
            carry = v >> 32;
        }
        return carry == 0;
    }
    bool fits(int bits) const {
        for (int k = 0; k < BIG_WORDS; ++k) {
            const int base = 32 * k;
            if (base >= bits ? w[k] != 0 : (bits - base < 32 && (w[k] >> (bits - base)) != 0)) return false;
        }
        return true;
    }
};

int field_bits(int k) {
    switch (k) {
        case 0: return 3;
        case 1: return 2;
        case 2: case 10: case 13: return MT_FEED_W;
        case 11: return MT_NW;
        case 12: return MT_PF + 1;
        case 14: return MT_LEN_W;
        case 15: return MT_ZW;
        default: return MT_W;
    }
}

struct Command {
    Big field[NFIELDS];
};

// Port setters: up to 64 bits a plain integer, wider a VlWide of 32-bit words.
template <typename T>
void put(T& port, const Big& value) { port = static_cast<T>(value.low()); }
template <std::size_t N>
void put(VlWide<N>& port, const Big& value) {
    for (std::size_t k = 0; k < N; ++k) port[k] = k < BIG_WORDS ? value.w[k] : 0;
}

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

std::string read_file(const char* path, const char* what) {
    FILE* f = std::fopen(path, "rb");
    if (!f) fail(std::string("cannot read the ") + what + " " + path + ": " + std::strerror(errno));
    std::string text;
    char chunk[1 << 16];
    size_t n;
    while ((n = std::fread(chunk, 1, sizeof chunk, f)) > 0) text.append(chunk, n);
    std::fclose(f);
    return text;
}

// Reads the whole command file; any bad line ends the run with one message.
std::vector<Command> read_commands(const char* path) {
    const std::string text = read_file(path, "command file");
    // allowed ranges: kind 3 bits, plane 2 bits, x .. l signed W bits or unsigned W bits
    // (a dwell's cycle count), the others unsigned of their port width
    const int64_t lo_w = MT_W >= 64 ? INT64_MIN : -(int64_t(1) << (MT_W - 1));
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
            const bool negative = q < eol && *q == '-';
            if (q < eol && (*q == '-' || *q == '+')) ++q;
            const char* digits = q;
            Big value;
            bool ok = true;
            while (q < eol && *q >= '0' && *q <= '9') ok = value.push_digit(unsigned(*q++ - '0')) && ok;
            if (q == digits || (q < eol && *q != ' ' && *q != '\t' && *q != '\r'))
                fail(where + USAGE + ", got \"" + shown(p, eol) + "\"");
            const int bits = field_bits(k);
            const bool signed_field = k >= 3 && k <= 9;
            if (negative) {
                // -v in W bits: only the signed fields, v <= 2^(W-1)
                ok = ok && signed_field && value.fits(64) && (value.zero() || value.low() - 1 <= uint64_t(-(lo_w + 1)));
                if (ok) {
                    const uint64_t v = (0 - value.low()) & mask(bits);
                    value = Big{};
                    value.w[0] = uint32_t(v);
                    value.w[1] = uint32_t(v >> 32);
                }
            } else {
                ok = ok && value.fits(bits);
            }
            if (!ok)
                fail(where + FIELD_NAMES[k] + " " + std::string(start, q) + " is out of range (kind 0 .. 7, plane 0 .. 3, " +
                     "x .. l " + std::to_string(MT_W) + "-bit integers, the others unsigned: feed, limit, cost " +
                     std::to_string(MT_FEED_W) + " bits, exit " + std::to_string(MT_NW) + ", rate " +
                     std::to_string(MT_PF + 1) + ", length " + std::to_string(MT_LEN_W) + ", budget " +
                     std::to_string(MT_ZW) + ")");
            cmd.field[k] = value;
        }
        while (q < eol && (*q == ' ' || *q == '\t' || *q == '\r')) ++q;
        if (q != eol) fail(where + USAGE + ", got \"" + shown(p, eol) + "\"");
#ifndef HAS_PLANE
        if (!cmd.field[1].zero()) fail(where + "plane " + std::to_string(cmd.field[1].low()) +
                                       ", but this motion_top has no cmd_plane port (use 0)");
#endif
        commands.push_back(cmd);
        p = eol + 1;
    }
    return commands;
}

// A control: at `cycle`, hold (1), resume (0) or override (percent).
struct Control {
    uint64_t cycle;
    int kind;           // 0 hold, 1 resume, 2 override
    uint64_t value;
};

std::vector<Control> read_controls(const char* path) {
    std::vector<Control> controls;
    if (!path) return controls;
    const std::string text = read_file(path, "controls file");
    size_t pos = 0;
    for (long line = 1; pos < text.size(); ++line) {
        size_t eol = text.find('\n', pos);
        if (eol == std::string::npos) eol = text.size();
        const std::string row = text.substr(pos, eol - pos);
        pos = eol + 1;
        char word[32];
        unsigned long long cycle = 0, value = 0;
        const int got = std::sscanf(row.c_str(), "%llu %31s %llu", &cycle, word, &value);
        if (got <= 0) continue;                 // blank
        const std::string kind = got >= 2 ? word : "";
        Control c{cycle, kind == "hold" ? 0 : kind == "resume" ? 1 : kind == "override" ? 2 : -1, value};
        if (got < 2 || c.kind < 0 || (c.kind == 2 && (got < 3 || value > 255)) ||
            (!controls.empty() && cycle < controls.back().cycle))
            fail(std::string(path) + " line " + std::to_string(line) +
                 ": want \"CYCLE hold|resume|override PERCENT\" (cycles not decreasing, percent 0 .. 255), got \"" +
                 row.substr(0, 60) + "\"");
        controls.push_back(c);
    }
    return controls;
}

// Periods after which a counter modulo 2^bits that moves by `step` a period is back
// (both are powers of two, so the larger of two such numbers is a multiple of the other).
uint64_t cycle_of(uint64_t step, int bits) {
    step &= mask(bits);
    uint64_t n = 1;
    while (step && bits > 0 && !(step & 1)) {
        step >>= 1;
        --bits;
    }
    if (step) n = bits >= 63 ? (1ULL << 62) : (1ULL << bits);
    return n;
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

// The command inputs (cmd_valid apart) from a command.
void push_fields(Vmotion_top& top, const Command& c) {
    top.cmd_kind = c.field[0].low();
#ifdef HAS_PLANE
    top.cmd_plane = c.field[1].low();
#endif
    put(top.cmd_feed, c.field[2]);
    put(top.cmd_x, c.field[3]);
    put(top.cmd_y, c.field[4]);
    put(top.cmd_z, c.field[5]);
    put(top.cmd_i, c.field[6]);
    put(top.cmd_j, c.field[7]);
    put(top.cmd_k, c.field[8]);
    put(top.cmd_l, c.field[9]);
    put(top.cmd_limit, c.field[10]);
    put(top.cmd_exit, c.field[11]);
    put(top.cmd_rate, c.field[12]);
    put(top.cmd_cost, c.field[13]);
    put(top.cmd_length, c.field[14]);
    put(top.cmd_budget, c.field[15]);
}

int main(int argc, char** argv) {
    const char *commands_path = nullptr, *steps_path = nullptr, *result_path = nullptr, *vcd_path = nullptr,
               *controls_path = nullptr;
    uint64_t max_cycles = 0, timing[3] = {1, 0, 0}, settings[4] = {1, 0, 0, 100}, push_interval = 1;
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
        else if (opt == "--controls") controls_path = value;
        else if (opt == "--settings") {
            std::string t = value;
            const uint64_t top[4] = {mask(MT_FEED_W), 15, 15, 255};
            for (int k = 0; k < 4; ++k) {
                const size_t comma = t.find(',');
                if ((comma == std::string::npos) != (k == 3))
                    fail("--settings wants SPEED_QUANTUM,BLOCK_SHIFT,JERK_SHIFT,OVERRIDE");
                settings[k] = number("--settings", t.substr(0, comma).c_str());
                if (settings[k] > top[k]) fail("--settings: a value out of range (quantum < 2^FEED_W, shifts 0 .. 15, "
                                               "override 0 .. 255)");
                t = comma == std::string::npos ? "" : t.substr(comma + 1);
            }
        }
        else if (opt == "--max-cycles") max_cycles = number("--max-cycles", value);
        else if (opt == "--progress-log2") progress_log2 = int(number("--progress-log2", value));
        else if (opt == "--push-interval") push_interval = number("--push-interval", value);
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
    if (push_interval < 1 || push_interval > 65536) fail("--push-interval must be 1 .. 65536");

    const std::vector<Command> commands = read_commands(commands_path);
    const std::vector<Control> controls = read_controls(controls_path);
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
    push_fields(*top, Command{});
    top->speed_quantum = settings[0];
    top->block_shift = settings[1];
    top->jerk_shift = settings[2];
    top->MT_OVERRIDE = settings[3];
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
    size_t next = 0, next_control = 0;
    uint64_t cycle = 0, rows = 0, last_push = 0;
    struct HoldStop {
        uint64_t hold, stopped, steps;     // steps: the row count at the hold, then the rows in between
        bool reached;
    };
    std::vector<HoldStop> stops;
    bool awaiting_stop = false;
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
    Counter acc = MT_COUNTER(motion_top__DOT__u_profile__DOT__u_ramp__DOT__acc, MT_ACC_W);
    Counter wa = MT_COUNTER(motion_top__DOT__u_profile__DOT__u_jerk__DOT__write_address, MT_WA_W);
    Counter since = MT_COUNTER(motion_top__DOT__u_out__DOT__since_fall, MT_SINCE_W);
    Counter count = MT_COUNTER(motion_top__DOT__u_out__DOT__count, MT_COUNT_W);
    Counter dwell = MT_COUNTER(motion_top__DOT__dwell_q, MT_DWELL_W);
    Counter* counters[] = {&acc, &wa, &since, &count, &dwell};
    // at rest: what the rules of acc and write_address need
    auto at_rest = [&] {
        return top->speed == 0 && root->motion_top__DOT__u_profile__DOT__u_ramp__DOT__n == 0 &&
               root->motion_top__DOT__u_profile__DOT__u_ramp__DOT__seg == 0 &&
               root->motion_top__DOT__u_profile__DOT__u_ramp__DOT__p == 0 &&
               root->motion_top__DOT__u_profile__DOT__u_jerk__DOT__total == 0 &&
               root->motion_top__DOT__u_profile__DOT__u_jerk__DOT__delta == 0;
    };
    // PERIOD: a multiple of every period of the rest of the state (see the header)
    const uint64_t PERIOD = 18ULL << settings[1];
    const bool debug_skip = std::getenv("MT_SKIP_DEBUG") != nullptr;   // why a stretch is not skipped
    uint64_t calm = 0, check_at = 8, skipped = 0, window = PERIOD;
#else
    (void)exact;
    const uint64_t skipped = 0;
#endif

    for (;;) {
        // inputs for the next rising edge, from the last sample (clk is low)
        bool control_now = false;
        while (next_control < controls.size() && controls[next_control].cycle <= cycle) {
            control_now = true;
            const Control& c = controls[next_control++];
            if (c.kind == 2) {
                top->MT_OVERRIDE = c.value;
            } else {
                if (c.kind == 0 && !top->hold) {
                    stops.push_back({c.cycle, 0, rows, false});
                    awaiting_stop = true;
                }
                if (c.kind == 1) awaiting_stop = false;
                top->hold = c.kind == 0;
            }
        }
        // the next rising edge is cycle + 1; a push no sooner than push_interval after the last
        const bool paced = next != 0 && next < total && cycle + 1 < last_push + push_interval;
        const bool push = next < total && !top->cmd_full && !paced;
        if (push) last_push = cycle + 1;
        if (push) {
            push_fields(*top, commands[next++]);
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
        if (awaiting_stop && top->stopped) {
            stops.back().stopped = cycle;
            stops.back().steps = rows - stops.back().steps;
            stops.back().reached = true;
            awaiting_stop = false;
        }
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
            bool active = push || paced || rise || top->error || control_now;
#ifdef HAS_EVENTS
            active = active || top->event_valid;
#endif
            if (active) {
                calm = 0;
                window = PERIOD;
            } else if (++calm == check_at) {
                std::memcpy(snapshot.data(), root, sizeof *root);
                for (Counter* c : counters) c->before = c->get();
            } else if (calm == check_at + PERIOD && window == PERIOD && at_rest()) {
                // modular counters: Verilator keeps values derived from them (the ramp's acc_n,
                // the filter's read address) as members computed after an edge, so they are
                // not patched: the window and the jump are whole numbers of their periods
                const uint64_t unit = PERIOD * std::max(cycle_of(acc.get() - acc.before, MT_ACC_W),
                                                        cycle_of(wa.get() - wa.before, MT_WA_W));
                if (unit > PERIOD && unit <= (PERIOD << 12)) window = unit;   // compare after `unit`
                else if (unit > PERIOD) calm = 0, check_at = 8;              // too long: no skip
            }
            if (calm != 0 && calm == check_at + window) {
                calm = 0;
                const uint64_t span = window;
                window = PERIOD;
                // the largest number of cycles every counter allows (0: none)
                uint64_t jump = at_rest() ? max_cycles - cycle - 1 : 0;       // cycle < max_cycles here
                if (next_control < controls.size())
                    jump = std::min(jump, controls[next_control].cycle > cycle ? controls[next_control].cycle - cycle - 1 : 0);
                const uint64_t s_now = since.get(), s_top = mask(MT_SINCE_W);
                if (s_now == s_top ? since.before != s_top : s_now != since.before + span) jump = 0;
                const uint64_t hold_time = top->hold_time;
                if (s_now != s_top && s_now + 1 < hold_time) jump = std::min(jump, hold_time - s_now - 2);
                const uint64_t c_now = count.get();
                if (c_now + span == count.before) jump = c_now >= 2 ? std::min(jump, c_now - 2) : 0;
                else if (c_now != count.before) jump = 0;
                const uint64_t d_now = dwell.get();
                if (d_now + span == dwell.before) jump = d_now >= 1 ? std::min(jump, d_now - 1) : 0;
                else if (d_now != dwell.before) jump = 0;
                if (acc.get() != acc.before || wa.get() != wa.before) jump = 0;
                jump -= jump % span;            // whole windows: the rest of the state repeats
                if (jump) {
                    for (Counter* c : counters) {
                        const uint64_t v = c->get();
                        std::memcpy(snapshot.data() + c->offset(root), &v, c->size);
                    }
                    if (std::memcmp(snapshot.data(), root, sizeof *root) != 0) {
                        if (debug_skip) {
                            const unsigned char* now = reinterpret_cast<const unsigned char*>(root);
                            for (size_t k = 0; k < sizeof *root; ++k)
                                if (snapshot[k] != now[k]) std::fprintf(stderr, "skip: cycle %" PRIu64 " byte %zu differs\n", cycle, k);
                        }
                        jump = 0;
                    }
                } else if (debug_skip) {
                    std::fprintf(stderr, "skip: cycle %" PRIu64 " rest %d\n", cycle, int(at_rest()));
                }
                if (jump) {
                    const uint64_t before = cycle;
                    if (s_now != s_top) since.set(jump >= s_top - s_now ? s_top : s_now + jump);
                    if (c_now + span == count.before) count.set(c_now - jump);
                    if (d_now + span == dwell.before) dwell.set(d_now - jump);
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
                 "\"commands\": %zu, \"skipped\": %" PRIu64 ", \"hold_stops\": [", rows, stopped ? "true" : "false", next,
                 next - size_t(top->queue_level), total, uint64_t(skipped));
    for (size_t k = 0; k < stops.size(); ++k) {
        if (stops[k].reached)
            std::fprintf(out, "%s[%" PRIu64 ", %" PRIu64 ", %" PRIu64 "]", k ? ", " : "", stops[k].hold,
                         stops[k].stopped, stops[k].steps);
        else
            std::fprintf(out, "%s[%" PRIu64 ", null, null]", k ? ", " : "", stops[k].hold);
    }
    std::fprintf(out, "]}\n");
    if (std::fclose(out) != 0) fail(std::string("cannot write ") + result_path);
    top->final();
    return 0;
}
