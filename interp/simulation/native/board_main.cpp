// SPDX-License-Identifier: Apache-2.0
// Native Verilator harness for rtl/uart_controller.v: the whole board-level design
// (UART link + controller + motion_top) driven bit by bit through its UART pins, in
// lockstep with a host program (interp/link/simlink.py) over stdin / stdout.
//
//   board_sim --clock-hz HZ --baud B [--steps FILE] [--line-noise P] [--seed S] [--exact 1]
//
// The bridge protocol: one request line on stdin, one answer line on stdout.
//   w HEX            queue the bytes (hex) to be shifted onto uart_rx, 8N1, LSB first, at
//                    CLK_HZ / BAUD clocks a bit (fractional: bit n of a burst starts at
//                    cycle origin + floor(n * CLK_HZ / BAUD)), from the current cycle on
//                    (after the bytes still queued).  Answer "ok CYCLE".
//   r SIZE CYCLES    run until SIZE bytes have come from uart_tx (since the last answer)
//                    or CYCLES cycles have passed (0: just report).  Answer
//                    "d CYCLE HEX" with every byte received since the last "d".
//   p NAME VALUE     set an input pin: estop, limit (3 bits), probe, or rst (the design's reset,
//                    as a board's button: held while 1).  Answer "ok CYCLE".
//   s AXIS SIDE AT   a limit switch on axis 0..2 (x, y, z) at harness position AT (steps
//                    counted at the pins, 0 at reset): SIDE 0 active at or below AT, 1 at
//                    or above; from then on that limit bit follows the position after
//                    every step (a machine's switch: homing).  Answer "ok CYCLE".
//   t AXIS SIDE AT   a probe touch on axis 0..2 at harness position AT, SIDE as for s: from
//                    then on the probe pin is high while any such touch is reached (a
//                    touch plate, an edge: probing).  Answer "ok CYCLE".
//   q                finish: close the steps CSV, answer one JSON line, exit 0.
// CYCLE: rising edges of clk since reset was released (simulated seconds = CYCLE / CLK_HZ).
//
// Noise (--line-noise P, --seed S): every bit of a character (start, 8 data, stop) in
// either direction is flipped with probability P by a seeded generator (std::mt19937_64),
// so a run is the same for the same seed whatever the host's speed.  Host -> controller:
// the flipped bits are what uart_rx sees.  Controller -> host: uart_tx is sampled in the
// middle of each bit (the bit times counted from the falling edge of the start bit at
// the nominal CLK_HZ / BAUD), the sample flipped with P; a start sample of 1 or a stop
// sample of 0 drops the character (a framing error, counted).
//
// Steps CSV (--steps): "cycle,dx,dy,dz" as `interp gcode --steps` writes it: one row per
// cycle with a rising edge on a step pin (d = -1 if its dir pin is set, else 1), the
// cycle counted as motion_main.cpp counts it: the rising edge at which the first command
// is pushed into motion_top (its cmd_valid high and cmd_full low) is cycle 1; if motion_top's
// hold input is high then (the host primed the queue under a feed hold), the first rising
// edge after that with hold low is cycle 1.
// Position: the harness counts the pulses at the step pins.
//
// Quiet stretches (off with --exact 1): while a read waits, nothing is being shifted in
// or out and motion_top is not busy, the model's whole state (Verilator's root object) is
// compared with a snapshot; when it is bit-identical to itself P cycles earlier with the
// inputs constant and no step, pin or uart_tx change in between, every following period
// of P cycles is the same, and the read's remaining whole periods are skipped in one jump.
//
// Free-running counters (BC_FREE_COUNTERS: uart_controller's heartbeat `beat`, +1 every
// cycle, wrapping; only the LEDs read it) are left out of the comparison: each must have
// moved by exactly P in the period, and it is moved on by the jump.
//
// Compile-time settings (harness_config.h, written by interp/simulation/native/build.py):
// BC_PUSH_VALID, BC_PUSH_FULL: root members of motion_top's cmd_valid and cmd_full
// (kept by the build's Verilator configuration file); BC_FREE_COUNTERS: a list of
// BC_FREE(member, bits) (may be empty); BC_HOLD, BC_BUSY: motion_top's hold input and busy output.
// Bad input: one line on stderr, exit status 2.
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "harness_config.h"     // generated in the build folder
#include "Vuart_controller.h"
#include "Vuart_controller___024root.h"
#include "verilated.h"

namespace {

[[noreturn]] void fail(const std::string& text) {
    std::fprintf(stderr, "%s\n", text.c_str());
    std::exit(2);
}

uint64_t number(const char* name, const char* text) {
    char* end;
    errno = 0;
    const unsigned long long v = std::strtoull(text, &end, 10);
    if (errno || *end || !*text || text[0] == '-') fail(std::string("bad ") + name + " " + text);
    return v;
}

int hex_digit(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

class Board {
  public:
    Board(uint64_t clock_hz, uint64_t baud, double noise, uint64_t seed, const char* steps_path, bool exact)
        : clock_hz_(clock_hz), baud_(baud), noise_(noise), rng_(seed), exact_(exact) {
        if (steps_path) {
            steps_ = std::fopen(steps_path, "wb");
            if (!steps_) fail(std::string("cannot write ") + steps_path + ": " + std::strerror(errno));
            std::fputs("cycle,dx,dy,dz\n", steps_);
        }
        top_ = std::make_unique<Vuart_controller>(context_.get(), "uart_controller");
        snapshot_.resize(sizeof *top_->rootp);
#define BC_FREE(member, bits) free_.push_back(Free{&top_->rootp->member, sizeof top_->rootp->member, bits, 0, \
    size_t(reinterpret_cast<unsigned char*>(&top_->rootp->member) - reinterpret_cast<unsigned char*>(top_->rootp))});
        BC_FREE_COUNTERS
#undef BC_FREE
        // reset: idle inputs, rst for two rising edges
        top_->clk = 0;
        top_->rst = 1;
        top_->uart_rx = 1;
        top_->estop = 0;
        top_->limit = 0;
        top_->probe = 0;
        top_->eval();
        for (int k = 0; k < 2; ++k) {
            top_->clk = 1;
            top_->eval();
            top_->clk = 0;
            top_->eval();
        }
        top_->rst = 0;
        top_->eval();
        prev_tx_ = top_->uart_tx;
        prev_step_ = top_->step;
    }

    uint64_t cycle() const { return cycle_; }

    void queue(const std::vector<uint8_t>& bytes) {
        for (uint8_t b : bytes) out_queue_.push_back(b);
    }

    void set_switch(int axis, int side, int64_t at) {
        switch_on_[axis] = true;
        switch_side_[axis] = side;
        switch_at_[axis] = at;
        update_switches();
        calm_ = 0;
    }

    void set_touch(int axis, int side, int64_t at) {
        touch_on_[axis] = true;
        touch_side_[axis] = side;
        touch_at_[axis] = at;
        update_switches();
        calm_ = 0;
    }

    void set_pin(const std::string& name, uint64_t value) {
        if (name == "estop") top_->estop = value & 1;
        else if (name == "limit") top_->limit = value & 7;
        else if (name == "probe") top_->probe = value & 1;
        else if (name == "rst") top_->rst = value & 1;
        else fail("unknown pin " + name + " (estop, limit, probe, rst)");
        calm_ = 0;
    }

    // Run until `size` bytes wait for the host or `cycles` cycles have passed.
    void run(uint64_t size, uint64_t cycles) {
        const uint64_t end = cycle_ + cycles;
        while (cycle_ < end && received_.size() < size) {
            if (!exact_ && try_skip(end)) continue;
            tick();
        }
    }

    std::vector<uint8_t> take() {
        std::vector<uint8_t> out(received_.begin(), received_.end());
        received_.clear();
        return out;
    }

    void finish(double wall_seconds) {
        if (steps_ && std::fclose(steps_) != 0) fail("cannot write the steps CSV");
        steps_ = nullptr;
        std::printf("{\"cycles\": %" PRIu64 ", \"first_push\": %" PRId64 ", \"steps\": %" PRIu64
                    ", \"position\": [%" PRId64 ", %" PRId64 ", %" PRId64 "], \"bits_to_device\": %" PRIu64
                    ", \"flipped_to_device\": %" PRIu64 ", \"bits_from_device\": %" PRIu64
                    ", \"flipped_from_device\": %" PRIu64 ", \"chars_from_device\": %" PRIu64
                    ", \"chars_dropped\": %" PRIu64 ", \"skipped\": %" PRIu64 ", \"wall_seconds\": %.3f}\n",
                    cycle_, first_push_ ? int64_t(first_push_) : int64_t(-1), rows_, position_[0], position_[1],
                    position_[2], bits_out_, flipped_out_, bits_in_, flipped_in_, chars_in_, dropped_, skipped_,
                    wall_seconds);
        std::fflush(stdout);
        top_->final();
    }

  private:
    bool flip() { return noise_ > 0 && uniform_(rng_) < noise_; }

    // the cycle at which bit n of the current burst starts
    uint64_t bit_start(uint64_t n) const {
        return origin_ + uint64_t((unsigned __int128)n * clock_hz_ / baud_);
    }

    void load_char() {
        const uint8_t b = out_queue_.front();
        out_queue_.pop_front();
        for (int k = 0; k < 10; ++k) {
            int v = k == 0 ? 0 : k == 9 ? 1 : (b >> (k - 1)) & 1;
            if (flip()) {
                v ^= 1;
                ++flipped_out_;
            }
            bits_[k] = uint8_t(v);
        }
        bits_out_ += 10;
    }

    // uart_rx for the rising edge numbered `edge`
    uint8_t rx_line(uint64_t edge) {
        if (sending_ && edge >= bit_start(bit_ + 1)) {
            ++bit_;
            if (bit_ % 10 == 0) {
                if (out_queue_.empty()) sending_ = false;
                else load_char();
            }
        }
        if (!sending_ && !out_queue_.empty()) {
            sending_ = true;
            origin_ = edge;
            bit_ = 0;
            load_char();
        }
        return sending_ ? bits_[bit_ % 10] : 1;
    }

    void tick() {
        const uint64_t edge = cycle_ + 1;
        top_->uart_rx = rx_line(edge);
        top_->clk = 0;
        top_->eval();
        const bool push = (BC_PUSH_VALID) && !(BC_PUSH_FULL);
        pushed_ = pushed_ || push;
        if (pushed_ && !first_push_ && !(BC_HOLD)) first_push_ = edge;
        top_->clk = 1;
        top_->eval();
        cycle_ = edge;
        activity_ = push;

        const unsigned step = top_->step;
        const unsigned rise = step & ~prev_step_;
        prev_step_ = step;
        if (rise) {
            int d[3];
            for (int k = 0; k < 3; ++k) {
                d[k] = rise >> k & 1 ? ((top_->dir >> k & 1) ? -1 : 1) : 0;
                position_[k] += d[k];
            }
            ++rows_;
            update_switches();
            if (steps_) {
                const int64_t c = first_push_ ? int64_t(cycle_ - first_push_ + 1) : -int64_t(cycle_);
                std::fprintf(steps_, "%" PRId64 ",%d,%d,%d\n", c, d[0], d[1], d[2]);
            }
            activity_ = true;
        }
        sample_tx();
    }

    void sample_tx() {
        const uint8_t tx = top_->uart_tx;
        if (tx != prev_tx_) activity_ = true;
        if (!receiving_) {
            if (prev_tx_ && !tx) {            // the start bit's falling edge
                receiving_ = true;
                start_ = cycle_;
                sample_ = 0;
                value_ = 0;
                framing_ok_ = true;
            }
        }
        prev_tx_ = tx;
        if (!receiving_) return;
        // bit k sampled at start + floor((2k + 1) * CLK / (2 BAUD))
        const uint64_t at = start_ + uint64_t((unsigned __int128)(2 * sample_ + 1) * clock_hz_ / (2 * baud_));
        if (cycle_ < at) return;
        int v = tx;
        ++bits_in_;
        if (flip()) {
            v ^= 1;
            ++flipped_in_;
        }
        if (sample_ == 0 && v != 0) framing_ok_ = false;
        else if (sample_ >= 1 && sample_ <= 8) value_ |= uint8_t(v << (sample_ - 1));
        else if (sample_ == 9 && v != 1) framing_ok_ = false;
        if (++sample_ == 10) {
            receiving_ = false;
            if (framing_ok_) {
                received_.push_back(value_);
                ++chars_in_;
            } else {
                ++dropped_;
            }
        }
    }

    // Quiet stretches (see the header): true if it skipped (or advanced) towards `end`.
    bool try_skip(uint64_t end) {
        constexpr uint64_t MIN_CALM = 64, MAX_PERIOD = 1 << 16;
        const bool idle = !sending_ && out_queue_.empty() && !receiving_ && !activity_ && !(BC_BUSY);
        if (!idle) {
            calm_ = 0;
            return false;
        }
        ++calm_;
        if (calm_ < MIN_CALM || end - cycle_ < 4 * MIN_CALM) return false;
        if (calm_ == MIN_CALM) {
            std::memcpy(snapshot_.data(), top_->rootp, snapshot_.size());
            for (Free& f : free_) f.before = f.get();
            snap_cycle_ = cycle_;
            return false;
        }
        const uint64_t period = cycle_ - snap_cycle_;
        if (period > MAX_PERIOD) {           // no short period: look again later
            calm_ = 0;
            return false;
        }
        for (Free& f : free_) {                  // counters: moved by the period, else no repeat
            if (((f.get() - f.before) & f.mask()) != (period & f.mask())) return false;
            std::memcpy(snapshot_.data() + f.offset, f.at, f.size);
        }
        const bool same = std::memcmp(snapshot_.data(), top_->rootp, snapshot_.size()) == 0;
        for (Free& f : free_) {
            const uint64_t v = f.before;
            std::memcpy(snapshot_.data() + f.offset, &v, f.size);
        }
        if (!same) return false;
        const uint64_t jump = (end - cycle_) / period * period;
        calm_ = 0;
        if (!jump) return false;
        for (Free& f : free_) f.set(f.get() + jump);
        cycle_ += jump;
        skipped_ += jump;
        return true;
    }

    std::unique_ptr<VerilatedContext> context_ = std::make_unique<VerilatedContext>();
    std::unique_ptr<Vuart_controller> top_;
    uint64_t clock_hz_, baud_;
    double noise_;
    std::mt19937_64 rng_;
    std::uniform_real_distribution<double> uniform_{0.0, 1.0};
    bool exact_;
    FILE* steps_ = nullptr;
    uint64_t cycle_ = 0, first_push_ = 0, rows_ = 0;
    int64_t position_[3] = {0, 0, 0};
    bool switch_on_[3] = {false, false, false};
    int switch_side_[3] = {0, 0, 0};
    int64_t switch_at_[3] = {0, 0, 0};
    bool touch_on_[3] = {false, false, false};
    int touch_side_[3] = {0, 0, 0};
    int64_t touch_at_[3] = {0, 0, 0};

    bool reached(int k, int side, int64_t at) const {
        return side ? position_[k] >= at : position_[k] <= at;
    }

    // the limit pins of the axes with a switch, and the probe pin of the touches, from the position
    void update_switches() {
        unsigned limit = top_->limit;
        bool touched = false, touching = false;
        for (int k = 0; k < 3; ++k) {
            if (switch_on_[k])
                limit = reached(k, switch_side_[k], switch_at_[k]) ? limit | 1u << k : limit & ~(1u << k);
            if (touch_on_[k]) {
                touching = true;
                touched = touched || reached(k, touch_side_[k], touch_at_[k]);
            }
        }
        top_->limit = limit;
        if (touching) top_->probe = touched;
    }
    unsigned prev_step_ = 0;
    bool activity_ = false, pushed_ = false;
    // host -> controller shifter
    std::deque<uint8_t> out_queue_;
    bool sending_ = false;
    uint64_t origin_ = 0, bit_ = 0;
    uint8_t bits_[10] = {};
    // controller -> host receiver
    std::deque<uint8_t> received_;
    uint8_t prev_tx_ = 1, value_ = 0;
    bool receiving_ = false, framing_ok_ = true;
    uint64_t start_ = 0;
    int sample_ = 0;
    // statistics
    uint64_t bits_out_ = 0, flipped_out_ = 0, bits_in_ = 0, flipped_in_ = 0, chars_in_ = 0, dropped_ = 0;
    // quiet stretches
    struct Free {
        void* at;
        size_t size;
        int bits;
        uint64_t before;
        size_t offset;
        uint64_t mask() const { return bits >= 64 ? ~0ULL : (1ULL << bits) - 1; }
        uint64_t get() const {
            uint64_t v = 0;
            std::memcpy(&v, at, size);
            return v & mask();
        }
        void set(uint64_t v) {
            v &= mask();
            std::memcpy(at, &v, size);
        }
    };
    std::vector<Free> free_;
    std::vector<unsigned char> snapshot_;
    uint64_t calm_ = 0, snap_cycle_ = 0, skipped_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
    const char* steps_path = nullptr;
    uint64_t clock_hz = 0, baud = 0, seed = 1;
    double noise = 0.0;
    bool exact = false;
    for (int a = 1; a < argc; ++a) {
        const std::string opt = argv[a];
        if (a + 1 >= argc) fail("option " + opt + " needs a value");
        const char* value = argv[++a];
        if (opt == "--steps") steps_path = value;
        else if (opt == "--clock-hz") clock_hz = number("--clock-hz", value);
        else if (opt == "--baud") baud = number("--baud", value);
        else if (opt == "--seed") seed = number("--seed", value);
        else if (opt == "--exact") exact = number("--exact", value) != 0;
        else if (opt == "--line-noise") {
            char* end;
            noise = std::strtod(value, &end);
            if (*end || !(noise >= 0.0 && noise <= 1.0)) fail(std::string("bad --line-noise ") + value + " (0 .. 1)");
        } else fail("unknown option " + opt);
    }
    if (!clock_hz || !baud) fail("need --clock-hz and --baud (both > 0)");
    if (baud * 2 > clock_hz) fail("--baud must be at most half of --clock-hz");

    const auto wall = std::chrono::steady_clock::now();
    Board board(clock_hz, baud, noise, seed, steps_path, exact);
    std::string line;
    char chunk[4096];
    for (;;) {
        line.clear();
        while (std::fgets(chunk, sizeof chunk, stdin)) {
            line += chunk;
            if (!line.empty() && line.back() == '\n') break;
        }
        if (line.empty()) break;                  // the host went away: end quietly
        while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
        const char op = line[0];
        const std::string rest = line.size() > 2 ? line.substr(2) : "";
        if (op == 'w') {
            if (rest.size() % 2) fail("w: odd number of hex digits");
            std::vector<uint8_t> bytes;
            for (size_t k = 0; k < rest.size(); k += 2) {
                const int hi = hex_digit(rest[k]), lo = hex_digit(rest[k + 1]);
                if (hi < 0 || lo < 0) fail("w: bad hex digit");
                bytes.push_back(uint8_t(hi << 4 | lo));
            }
            board.queue(bytes);
            std::printf("ok %" PRIu64 "\n", board.cycle());
        } else if (op == 'r') {
            unsigned long long size = 0, cycles = 0;
            if (std::sscanf(rest.c_str(), "%llu %llu", &size, &cycles) != 2) fail("r: want SIZE CYCLES");
            board.run(size, cycles);
            std::printf("d %" PRIu64 " ", board.cycle());
            for (uint8_t b : board.take()) std::printf("%02x", b);
            std::printf("\n");
        } else if (op == 'p') {
            char name[32];
            unsigned long long value = 0;
            if (std::sscanf(rest.c_str(), "%31s %llu", name, &value) != 2) fail("p: want NAME VALUE");
            board.set_pin(name, value);
            std::printf("ok %" PRIu64 "\n", board.cycle());
        } else if (op == 's' || op == 't') {     // a limit switch, a probe touch
            int axis = 0, side = 0;
            long long at = 0;
            if (std::sscanf(rest.c_str(), "%d %d %lld", &axis, &side, &at) != 3 || axis < 0 || axis > 2 ||
                side < 0 || side > 1)
                fail(std::string(1, op) + ": want AXIS (0..2) SIDE (0 or 1) AT");
            if (op == 's')
                board.set_switch(axis, side, at);
            else
                board.set_touch(axis, side, at);
            std::printf("ok %" PRIu64 "\n", board.cycle());
        } else if (op == 'q') {
            board.finish(std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count());
            return 0;
        } else {
            fail("unknown request \"" + line.substr(0, 40) + "\"");
        }
        std::fflush(stdout);
    }
    return 0;
}
