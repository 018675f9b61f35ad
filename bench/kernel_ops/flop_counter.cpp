// An Oclgrind plugin that counts the floating-point operations a kernel launch executes, lane by
// lane (docs/BENCHMARKS.md, "Kernels against the device's peak (issue 36)"). Oclgrind's own
// --inst-counts counts an `fadd` of a float16 once; this counts it 16 times, from the width of the
// value the instruction produced. Built and run by scripts/count_kernel_ops.sh:
//   oclgrind --plugins build-ops/libflop_counter.so brdfbake lut --size 8 ...
// Each launch appends one JSON line to $BRDFBAKE_FLOP_COUNTS (else stderr):
//   {"kernel": NAME, "work_items": N, "flops": F, "fp64_flops": F64, "add": .., "mul": .., "fma": ..,
//    "div": .., "sqrt": .., "transcendental": .., "global_load_bytes": .., "global_store_bytes": ..}
// Bytes: every load and store of global (and, loaded, constant) memory, vloadN/vstoreN included.
// What counts as a flop (per lane): fadd, fsub, fmul, fdiv 1; fma/fmuladd/mad 2; sqrt, rsqrt 1; each
// transcendental builtin (exp, log, pow, sin, cos, tan, acos, asin, atan, atan2, exp2, log2, sincos) 1;
// dot of n lanes 2n - 1, length 2n, normalize 3n, cross 9, mix 3, distance 3n. fneg, fabs, fmin,
// fmax, clamp, floor, comparisons, conversions and selects are not flops.
//
// Only Oclgrind's plugin interface (21.10) is declared here: the virtual functions in its order,
// and the value an instruction produced (its size per lane and lane count).
#include <llvm/IR/Function.h>
#include <llvm/IR/Instructions.h>
#include <llvm/IR/Type.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

typedef uint64_t cl_mem_flags, cl_map_flags;

namespace oclgrind {
class Context;
class KernelInvocation;
class Memory;
class WorkGroup;
class WorkItem;
enum AtomicOp : int {};
enum MessageType : int {};
struct TypedValue {
  unsigned size;  // bytes per lane
  unsigned num;   // lanes
  unsigned char* data;
};
class Plugin {
 public:
  Plugin(const Context* context);
  virtual ~Plugin();
  virtual void hostMemoryLoad(const Memory*, size_t, size_t) {}
  virtual void hostMemoryStore(const Memory*, size_t, size_t, const uint8_t*) {}
  virtual void instructionExecuted(const WorkItem*, const llvm::Instruction*, const TypedValue&) {}
  virtual void kernelBegin(const KernelInvocation*) {}
  virtual void kernelEnd(const KernelInvocation*) {}
  virtual void log(MessageType, const char*) {}
  virtual void memoryAllocated(const Memory*, size_t, size_t, cl_mem_flags, const uint8_t*) {}
  virtual void memoryAtomicLoad(const Memory*, const WorkItem*, AtomicOp, size_t, size_t) {}
  virtual void memoryAtomicStore(const Memory*, const WorkItem*, AtomicOp, size_t, size_t) {}
  virtual void memoryDeallocated(const Memory*, size_t) {}
  virtual void memoryLoad(const Memory*, const WorkItem*, size_t, size_t) {}
  virtual void memoryLoad(const Memory*, const WorkGroup*, size_t, size_t) {}
  virtual void memoryMap(const Memory*, size_t, size_t, size_t, cl_map_flags) {}
  virtual void memoryStore(const Memory*, const WorkItem*, size_t, size_t, const uint8_t*) {}
  virtual void memoryStore(const Memory*, const WorkGroup*, size_t, size_t, const uint8_t*) {}
  virtual void memoryUnmap(const Memory*, size_t, const void*) {}
  virtual void workGroupBarrier(const WorkGroup*, uint32_t) {}
  virtual void workGroupBegin(const WorkGroup*) {}
  virtual void workGroupComplete(const WorkGroup*) {}
  virtual void workItemBegin(const WorkItem*) {}
  virtual void workItemComplete(const WorkItem*) {}
  virtual void workItemBarrier(const WorkItem*) {}
  virtual void workItemClearBarrier(const WorkItem*) {}
  virtual bool isThreadSafe() const;

 protected:
  const Context* m_context;
};
class Context {
 public:
  void registerPlugin(Plugin* plugin);
  void unregisterPlugin(Plugin* plugin);
};
}  // namespace oclgrind

namespace {

struct Counts {
  std::string kernel;
  uint64_t work_items = 0;
  double flops = 0, fp64 = 0, add = 0, mul = 0, fma = 0, div = 0, sqrt = 0, trans = 0;
  double load = 0, store = 0;
};

// The builtin's name without its mangling: "_Z4sqrtDv8_f" -> "sqrt".
std::string builtin_name(const std::string& mangled) {
  if (mangled.rfind("_Z", 0) != 0) return mangled;
  size_t i = 2, n = 0;
  while (i < mangled.size() && mangled[i] >= '0' && mangled[i] <= '9') n = 10 * n + size_t(mangled[i++] - '0');
  return mangled.substr(i, n);
}

unsigned lanes_of(const llvm::Type* t) {
  if (const auto* v = llvm::dyn_cast<llvm::FixedVectorType>(t)) return v->getNumElements();
  return 1;
}

class FlopCounter : public oclgrind::Plugin {
 public:
  explicit FlopCounter(const oclgrind::Context* c) : Plugin(c) {}
  void kernelBegin(const oclgrind::KernelInvocation*) override { c_ = Counts(); }
  void workItemBegin(const oclgrind::WorkItem*) override { ++c_.work_items; }
  void instructionExecuted(const oclgrind::WorkItem*, const llvm::Instruction* in,
                           const oclgrind::TypedValue& result) override {
    if (c_.kernel.empty()) c_.kernel = in->getFunction()->getName().str();
    const unsigned op = in->getOpcode();
    const double lanes = result.num;
    const bool dbl = in->getType()->getScalarType()->isDoubleTy();
    auto flop = [&](double n, double& cat) {
      cat += n;
      c_.flops += n;
      if (dbl) c_.fp64 += n;
    };
    switch (op) {
      case llvm::Instruction::FAdd:
      case llvm::Instruction::FSub:
        flop(lanes, c_.add);
        return;
      case llvm::Instruction::FMul:
        flop(lanes, c_.mul);
        return;
      case llvm::Instruction::FDiv:
      case llvm::Instruction::FRem:
        flop(lanes, c_.div);
        return;
      case llvm::Instruction::Load: {
        const auto* l = llvm::cast<llvm::LoadInst>(in);
        if (l->getPointerAddressSpace() == 1 || l->getPointerAddressSpace() == 2)
          c_.load += double(result.size) * result.num;
        return;
      }
      case llvm::Instruction::Store: {
        const auto* s = llvm::cast<llvm::StoreInst>(in);
        if (s->getPointerAddressSpace() == 1)
          c_.store += double(s->getValueOperand()->getType()->getPrimitiveSizeInBits()) / 8.0;
        return;
      }
      case llvm::Instruction::Call:
        break;
      default:
        return;
    }
    const auto* call = llvm::cast<llvm::CallInst>(in);
    const llvm::Function* f = call->getCalledFunction();
    if (!f || !f->isDeclaration()) return;  // a function of the kernel: its body is counted
    const std::string name = f->getName().str();
    const bool arg_dbl = call->arg_size() > 0 && call->getArgOperand(0)->getType()->getScalarType()->isDoubleTy();
    const double arg_lanes = call->arg_size() > 0 ? lanes_of(call->getArgOperand(0)->getType()) : 1;
    auto flop_arg = [&](double n, double& cat) {
      cat += n;
      c_.flops += n;
      if (arg_dbl) c_.fp64 += n;
    };
    if (name.rfind("llvm.fmuladd", 0) == 0 || name.rfind("llvm.fma", 0) == 0) return flop(2 * lanes, c_.fma);
    if (name.rfind("llvm.sqrt", 0) == 0) return flop(lanes, c_.sqrt);
    if (name.rfind("llvm.", 0) == 0) return;  // fabs, minnum, lifetime, memcpy ...
    const std::string b = builtin_name(name);
    if (b.rfind("vload", 0) == 0 || b.rfind("vstore", 0) == 0) {  // vloadN, vstoreN, vload_half, vstore_half
      const bool load = b[1] == 'l', half = b.find("half") != std::string::npos;
      const unsigned pointer = load ? 1 : 2;
      if (call->arg_size() <= pointer || !call->getArgOperand(pointer)->getType()->isPointerTy()) return;
      const unsigned space = call->getArgOperand(pointer)->getType()->getPointerAddressSpace();
      if (load && (space == 1 || space == 2)) c_.load += half ? 2.0 * result.num : double(result.size) * result.num;
      if (!load && space == 1) {
        const llvm::Type* v = call->getArgOperand(0)->getType();
        c_.store += half ? 2.0 * lanes_of(v) : double(v->getPrimitiveSizeInBits()) / 8.0;
      }
      return;
    }
    if (b == "mad" || b == "fma") return flop_arg(2 * arg_lanes, c_.fma);
    if (b == "sqrt" || b == "rsqrt" || b == "native_sqrt" || b == "native_rsqrt") return flop_arg(arg_lanes, c_.sqrt);
    if (b == "dot") return flop_arg(2 * arg_lanes - 1, c_.fma);
    if (b == "length") return flop_arg(2 * arg_lanes, c_.fma);
    if (b == "distance") return flop_arg(3 * arg_lanes, c_.fma);
    if (b == "normalize") return flop_arg(3 * arg_lanes, c_.fma);
    if (b == "cross") return flop_arg(9, c_.fma);
    if (b == "mix") return flop_arg(3 * arg_lanes, c_.fma);
    static const char* const kTrans[] = {
        "exp",        "exp2",       "log",        "log2",        "pow",           "powr",        "pown",
        "sin",        "cos",        "tan",        "acos",        "asin",          "atan",        "atan2",
        "sinh",       "cosh",       "tanh",       "cbrt",        "hypot",         "sincos",      "native_exp",
        "native_log", "native_sin", "native_cos", "native_powr", "native_divide", "native_recip"};
    for (const char* t : kTrans)
      if (b == t) return flop_arg(arg_lanes, c_.trans);
  }
  void kernelEnd(const oclgrind::KernelInvocation*) override {
    char line[640];
    std::snprintf(line, sizeof line,
                  "{\"kernel\": \"%s\", \"work_items\": %llu, \"flops\": %.0f, \"fp64_flops\": %.0f, \"add\": %.0f, "
                  "\"mul\": %.0f, \"fma\": %.0f, \"div\": %.0f, \"sqrt\": %.0f, \"transcendental\": %.0f, "
                  "\"global_load_bytes\": %.0f, \"global_store_bytes\": %.0f}\n",
                  c_.kernel.c_str(), static_cast<unsigned long long>(c_.work_items), c_.flops, c_.fp64, c_.add, c_.mul,
                  c_.fma, c_.div, c_.sqrt, c_.trans, c_.load, c_.store);
    const char* path = std::getenv("BRDFBAKE_FLOP_COUNTS");
    FILE* out = path && *path ? std::fopen(path, "a") : nullptr;
    std::fputs(line, out ? out : stderr);
    if (out) std::fclose(out);
  }
  bool isThreadSafe() const override { return false; }  // and run it with --num-threads 1: the counters are plain

 private:
  Counts c_;
};

FlopCounter* g_counter = nullptr;

}  // namespace

extern "C" void initializePlugins(oclgrind::Context* context) {
  g_counter = new FlopCounter(context);
  context->registerPlugin(g_counter);
}

extern "C" void releasePlugins(oclgrind::Context* context) {
  context->unregisterPlugin(g_counter);
  delete g_counter;
  g_counter = nullptr;
}
