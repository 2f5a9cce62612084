// A QEMU TCG plugin (plugin API version 1, QEMU 7.2) that counts the guest instructions executed
// between a begin marker and an end marker: the per-jiffy cost of Indicator::step on the
// Cortex-M image (hal/cortexm/src/main.cpp: dw_step_begin, dw_step_end_idle, dw_step_end_active).
//   qemu-system-arm ... -plugin ./libqemu_insn_plugin.so,begin=0x...,idle=0x...,active=0x...,out=FILE
// FILE gets one line per jiffy: `idle <n>` or `active <n>`. Counting is per translation block:
// each executed block adds its instruction count (exact unless an exception leaves a block early;
// the image enables only SysTick, whose handler's instructions are then counted too, as they
// would be on the target).
//
// Debian's QEMU has plugin support but ships no qemu-plugin.h: the few declarations used are
// written out below from the documented, versioned C ABI.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" {
typedef std::uint64_t qemu_plugin_id_t;
struct qemu_info_t;
struct qemu_plugin_tb;
struct qemu_plugin_insn;
enum qemu_plugin_cb_flags { QEMU_PLUGIN_CB_NO_REGS, QEMU_PLUGIN_CB_R_REGS, QEMU_PLUGIN_CB_RW_REGS };
typedef void (*qemu_plugin_vcpu_tb_trans_cb_t)(qemu_plugin_id_t id, struct qemu_plugin_tb* tb);
typedef void (*qemu_plugin_vcpu_udata_cb_t)(unsigned int vcpu_index, void* userdata);
typedef void (*qemu_plugin_udata_cb_t)(qemu_plugin_id_t id, void* userdata);
void qemu_plugin_register_vcpu_tb_trans_cb(qemu_plugin_id_t id, qemu_plugin_vcpu_tb_trans_cb_t cb);
void qemu_plugin_register_vcpu_tb_exec_cb(struct qemu_plugin_tb* tb, qemu_plugin_vcpu_udata_cb_t cb,
                                          enum qemu_plugin_cb_flags flags, void* userdata);
std::size_t qemu_plugin_tb_n_insns(const struct qemu_plugin_tb* tb);
std::uint64_t qemu_plugin_tb_vaddr(const struct qemu_plugin_tb* tb);
void qemu_plugin_register_atexit_cb(qemu_plugin_id_t id, qemu_plugin_udata_cb_t cb, void* userdata);
void qemu_plugin_outs(const char* string);

__attribute__((visibility("default"))) extern const int qemu_plugin_version;
const int qemu_plugin_version = 1;
__attribute__((visibility("default"))) int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t* info, int argc,
                                                               char** argv);
}

namespace {

std::uint64_t g_begin = 0, g_idle = 0, g_active = 0;
std::uint64_t g_total = 0, g_start = 0;
bool g_inside = false;
std::FILE* g_out = nullptr;
std::uint64_t g_jiffies[2] = {0, 0}, g_sum[2] = {0, 0}, g_max[2] = {0, 0};

// The block's instruction count and role, packed into the callback's user data.
constexpr std::uint64_t kBegin = 1ull << 62, kIdle = 1ull << 61, kActive = 1ull << 60, kCount = (1ull << 60) - 1;

void on_exec(unsigned int, void* userdata) {
  const std::uint64_t data = reinterpret_cast<std::uintptr_t>(userdata);
  if (data & kBegin) {
    g_inside = true;
    g_start = g_total;
  }
  if ((data & (kIdle | kActive)) && g_inside) {
    const int kind = (data & kActive) ? 1 : 0;
    const std::uint64_t n = g_total - g_start;
    g_inside = false;
    ++g_jiffies[kind];
    g_sum[kind] += n;
    if (n > g_max[kind]) g_max[kind] = n;
    if (g_out) std::fprintf(g_out, "%s %" PRIu64 "\n", kind ? "active" : "idle", n);
  }
  g_total += data & kCount;
}

void on_translate(qemu_plugin_id_t, struct qemu_plugin_tb* tb) {
  const std::uint64_t pc = qemu_plugin_tb_vaddr(tb);
  std::uint64_t data = qemu_plugin_tb_n_insns(tb);
  if (pc == g_begin) data |= kBegin;
  if (pc == g_idle) data |= kIdle;
  if (pc == g_active) data |= kActive;
  qemu_plugin_register_vcpu_tb_exec_cb(tb, on_exec, QEMU_PLUGIN_CB_NO_REGS,
                                       reinterpret_cast<void*>(static_cast<std::uintptr_t>(data)));
}

void on_exit(qemu_plugin_id_t, void*) {
  char line[256];
  for (int kind = 0; kind < 2; ++kind) {
    const char* name = kind ? "active" : "idle";
    std::snprintf(line, sizeof line, "insn_%s_jiffies=%" PRIu64 "\ninsn_%s_mean=%" PRIu64 "\ninsn_%s_max=%" PRIu64 "\n",
                  name, g_jiffies[kind], name, g_jiffies[kind] ? g_sum[kind] / g_jiffies[kind] : 0, name, g_max[kind]);
    qemu_plugin_outs(line);
    if (g_out) std::fputs(line, g_out);
  }
  if (g_out) std::fclose(g_out);
  g_out = nullptr;
}

}  // namespace

extern "C" int qemu_plugin_install(qemu_plugin_id_t id, const qemu_info_t*, int argc, char** argv) {
  for (int i = 0; i < argc; ++i) {
    const char* eq = std::strchr(argv[i], '=');
    if (!eq) return -1;
    const std::size_t key = std::size_t(eq - argv[i]);
    // Thumb function symbols carry bit 0; the PC of a block does not.
    const std::uint64_t value = std::strtoull(eq + 1, nullptr, 0) & ~1ull;
    if (std::strncmp(argv[i], "begin", key) == 0) g_begin = value;
    else if (std::strncmp(argv[i], "idle", key) == 0) g_idle = value;
    else if (std::strncmp(argv[i], "active", key) == 0) g_active = value;
    else if (std::strncmp(argv[i], "out", key) == 0) g_out = std::fopen(eq + 1, "w");
    else return -1;
  }
  if (!g_begin || !g_idle || !g_active) return -1;
  qemu_plugin_register_vcpu_tb_trans_cb(id, on_translate);
  qemu_plugin_register_atexit_cb(id, on_exit, nullptr);
  return 0;
}
