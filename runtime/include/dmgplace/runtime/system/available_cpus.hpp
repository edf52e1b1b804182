#pragma once
// How many CPUs this process may run on: the CPU affinity mask (sched_getaffinity), which Slurm,
// cgroup cpusets and `taskset` set. std::thread::hardware_concurrency() counts the machine's CPUs
// and oversubscribes inside such a set. Every "0 = all cores" default uses this.
namespace dmgplace::runtime {

int available_cpus();

}  // namespace dmgplace::runtime
