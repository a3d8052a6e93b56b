#pragma once
// `suite list --counters`: the events this machine can count, and why the others cannot.
namespace suite {

int list_counters(bool json);

}  // namespace suite
