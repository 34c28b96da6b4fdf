#pragma once
/// Included once by each task plugin library: PODIUM_EXPORT_TASK(MyTask, "my_task") exports the
/// descriptor the loader checks before creating any object, and the create/destroy pair (objects
/// are destroyed by the library that made them).
#include <boost/dll/alias.hpp>

#include "podium/plugins/task.h"

namespace podium::plugins {

/// Checked by the loader before any C++ object crosses the boundary (DuckDB's habit).
struct TaskDescriptor {
  int abi_version;
  const char* podium_version;
  const char* compiler;
  const char* build_type;
  const char* task_name;
};

using CreateTaskFn = Task*();
using DestroyTaskFn = void(Task*);

}  // namespace podium::plugins

#ifndef PODIUM_PLUGIN_ABI_VERSION
#define PODIUM_PLUGIN_ABI_VERSION ::podium::plugins::kAbiVersion
#endif

// A test plugin (built by add_podium_task from tests/, or with an ABI_VERSION) also exports
// podium_test_only_task: `podium tasks` lists it only with --all (plugins::is_test_plugin).
#ifdef PODIUM_TEST_PLUGIN
#define PODIUM_EXPORT_TEST_MARK                         \
  namespace podium_plugin_exports {                     \
  extern "C" const int podium_test_only_task_value = 1; \
  }                                                     \
  BOOST_DLL_ALIAS(podium_plugin_exports::podium_test_only_task_value, podium_test_only_task)
#else
#define PODIUM_EXPORT_TEST_MARK
#endif

#define PODIUM_EXPORT_TASK(TaskClass, task_name_literal)                                                                      \
  namespace podium_plugin_exports {                                                                                           \
  extern "C" const ::podium::plugins::TaskDescriptor podium_task_descriptor_value = {                                         \
      PODIUM_PLUGIN_ABI_VERSION, PODIUM_PLUGIN_VERSION, PODIUM_PLUGIN_COMPILER, PODIUM_PLUGIN_BUILD_TYPE, task_name_literal}; \
  ::podium::plugins::Task* podium_create_task_impl() { return new TaskClass(); }                                              \
  void podium_destroy_task_impl(::podium::plugins::Task* task) { delete task; }                                               \
  }                                                                                                                           \
  BOOST_DLL_ALIAS(podium_plugin_exports::podium_task_descriptor_value, podium_task_descriptor)                                \
  BOOST_DLL_ALIAS(podium_plugin_exports::podium_create_task_impl, podium_create_task)                                         \
  BOOST_DLL_ALIAS(podium_plugin_exports::podium_destroy_task_impl, podium_destroy_task)                                       \
  PODIUM_EXPORT_TEST_MARK
