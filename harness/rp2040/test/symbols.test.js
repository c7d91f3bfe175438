// Symbol names in both manglings, as rustc writes them for the Pico image (legacy by default; v0 with
// `-C symbol-mangling-version=v0`, the default of newer compilers).

import assert from 'node:assert/strict';
import test from 'node:test';

import { demangle, findMethod } from '../src/symbols.js';

const LEGACY = {
  apply: '_ZN8firmware7runtime36Runtime$LT$P$C$E$C$_$C$_$C$_$C$_$GT$5apply17hdd4e144360e0e2dcE',
  decide: '_ZN8firmware7runtime36Runtime$LT$P$C$E$C$_$C$_$C$_$C$_$GT$6decide17hd4786b9392b9d2bfE',
  reset: '_ZN8firmware7runtime36Runtime$LT$P$C$E$C$_$C$_$C$_$C$_$GT$5reset17h3af8d1c87aa37cd9E',
  free: '_ZN8firmware7runtime16take_until_stuck17h2e1912b75cca1bd6E',
};
const V0 = {
  apply:
    '_RNvMs_NtCshVLd7lDb8fT_8firmware7runtimeINtB4_7RuntimeINtNtB6_6choice16RandomLocalQueueKj1_Kj3_ENtCs8eLuPuhuyM1_9cell_pico4RoscKB1n_Kja_Kb0_KB1r_E5applyB1x_',
  decide:
    '_RINvMs_NtCshVLd7lDb8fT_8firmware7runtimeINtB5_7RuntimeINtNtB7_6choice16RandomLocalQueueKj1_Kj3_ENtCs8eLuPuhuyM1_9cell_pico4RoscKB1o_Kja_Kb0_KB1s_E6decideNCINvMs_NtB7_4linkNtB2z_4Link7serviceBQ_B1w_KB1o_KB27_KB2b_KB1s_INtB1y_6DriverNtNtNtB1y_3app16shared_resources31outputs_that_needs_to_be_lockedEE0EB1y_',
  free: '_RINvNtCshVLd7lDb8fT_8firmware7runtime16take_until_stuckKj1_Kja_Kb0_Kj3_ECs8eLuPuhuyM1_9cell_pico',
  closure: '_RINvNvNtCs8eLuPuhuyM1_9cell_pico3app4main21___rtic_init_resourcesNCB2_0EB6_',
};

test('legacy names', () => {
  assert.equal(demangle(LEGACY.apply), 'firmware::runtime::Runtime<P,E,_,_,_,_>::apply');
  assert.equal(demangle(LEGACY.free), 'firmware::runtime::take_until_stuck');
});

test('v0 names, generic arguments, back references and closures', () => {
  assert.equal(
    demangle(V0.apply),
    '<firmware::runtime::Runtime<firmware::choice::RandomLocalQueue<1, 3>, cell_pico::Rosc, 1, 10, false, 3>>::apply',
  );
  assert.equal(
    demangle(V0.decide),
    '<firmware::runtime::Runtime<firmware::choice::RandomLocalQueue<1, 3>, cell_pico::Rosc, 1, 10, false, 3>>::decide::' +
      '<<firmware::link::Link>::service::<firmware::choice::RandomLocalQueue<1, 3>, cell_pico::Rosc, 1, 10, false, 3, ' +
      'cell_pico::Driver<cell_pico::app::shared_resources::outputs_that_needs_to_be_locked>>::{closure#0}>',
  );
  assert.equal(demangle(V0.free), 'firmware::runtime::take_until_stuck::<1, 10, false, 3>');
  assert.equal(
    demangle(V0.closure),
    'cell_pico::app::main::__rtic_init_resources::<cell_pico::app::main::{closure#0}>',
  );
});

test('not a Rust name, or a broken one, stays as it is', () => {
  for (const name of ['main', '_RNvC', '_ZN3foo', '_RB9999_', '_RNvNtCs_3abc']) assert.equal(demangle(name), name);
});

const FUNC = 2;
const symbols = (names) => names.map(([name, value]) => ({ name, value, size: 2, type: FUNC }));

test('finds the runtime entry points in either mangling, Thumb bit cleared', () => {
  for (const names of [LEGACY, V0]) {
    const table = symbols([[names.free, 0x10000801], [names.apply, 0x10000911], [names.decide, 0x10000a49]]);
    assert.equal(findMethod(table, 'firmware::runtime::Runtime', 'apply'), 0x10000910);
    assert.equal(findMethod(table, 'firmware::runtime::Runtime', 'decide'), 0x10000a48);
  }
});

test('a missing or ambiguous entry point is an error', () => {
  const table = symbols([[LEGACY.reset, 0x10000801], [LEGACY.apply, 0x10000911]]);
  assert.throws(() => findMethod(table, 'firmware::runtime::Runtime', 'decide'), /no function named firmware::runtime::Runtime<…>::decide/);
  const twice = symbols([[LEGACY.apply, 0x10000911], [V0.apply, 0x10000a01]]);
  assert.throws(() => findMethod(twice, 'firmware::runtime::Runtime', 'apply'), /2 functions named/);
  const data = [{ name: LEGACY.apply, value: 0x20000000, size: 4, type: 1 }];
  assert.throws(() => findMethod(data, 'firmware::runtime::Runtime', 'apply'), /no function/);
});
