// Rust symbol names, demangled enough to find functions by path: the legacy scheme
// (`_ZN8firmware7runtime…5apply17h…E` → `firmware::runtime::Runtime<P,E,_,_,_,_>::apply`) and the v0
// scheme (`_RNvM…5apply` → `<firmware::runtime::Runtime<…>>::apply`), which newer compilers use. The
// v0 reader follows the grammar of the Rust symbol-mangling RFC 2603 for paths, types and constants;
// generic arguments come out in full, constants as their value, closures as `{closure#N}`.

/** Thrown for a v0 name that does not follow the grammar (caught by `demangle`). */
class Malformed extends Error {}

const LEGACY_ESCAPES = {
  $SP$: '@',
  $BP$: '*',
  $RF$: '&',
  $LT$: '<',
  $GT$: '>',
  $LP$: '(',
  $RP$: ')',
  $C$: ',',
};

/** `name` demangled, or `name` itself when it is not a Rust symbol (or not one this reader knows). */
export function demangle(name) {
  try {
    if (name.startsWith('_ZN')) return legacy(name);
    if (name.startsWith('_R')) return new V0(name).symbol();
  } catch (e) {
    if (!(e instanceof Malformed)) throw e;
  }
  return name;
}

function legacy(name) {
  const parts = [];
  let i = 3;
  while (i < name.length && name[i] !== 'E') {
    const digits = /^\d+/.exec(name.slice(i));
    if (!digits) throw new Malformed(name);
    i += digits[0].length;
    const len = Number(digits[0]);
    if (i + len > name.length) throw new Malformed(name);
    parts.push(name.slice(i, i + len));
    i += len;
  }
  if (name[i] !== 'E') throw new Malformed(name);
  if (parts.length > 1 && /^h[0-9a-f]{16}$/.test(parts[parts.length - 1])) parts.pop();
  const unescape = (p) =>
    p
      .replace(/^_\$/, '$')
      .replace(/\$(SP|BP|RF|LT|GT|LP|RP|C)\$/g, (m) => LEGACY_ESCAPES[m])
      .replace(/\$u([0-9a-f]+)\$/g, (_, h) => String.fromCodePoint(parseInt(h, 16)))
      .replace(/\.\./g, '::');
  return parts.map(unescape).join('::');
}

const BASIC = {
  a: 'i8', b: 'bool', c: 'char', d: 'f64', e: 'str', f: 'f32', h: 'u8', i: 'isize', j: 'usize', l: 'i32',
  m: 'u32', n: 'i128', o: 'u128', s: 'i16', t: 'u16', u: '()', v: '...', x: 'i64', y: 'u64', z: '!',
  p: '_',
};

/** A recursive-descent reader of one v0 symbol (RFC 2603). */
class V0 {
  constructor(name) {
    this.s = name;
    this.i = 2; // after "_R"
    this.depth = 0;
  }

  peek() {
    return this.s[this.i];
  }

  eat(c) {
    if (this.s[this.i] === c) {
      this.i++;
      return true;
    }
    return false;
  }

  next() {
    if (this.i >= this.s.length) throw new Malformed(this.s);
    return this.s[this.i++];
  }

  /** base-62 number terminated by `_` (`_` alone is 0, digits give value + 1). */
  base62() {
    if (this.eat('_')) return 0;
    let n = 0;
    for (;;) {
      const c = this.next();
      if (c === '_') return n + 1;
      const d = '0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ'.indexOf(c);
      if (d < 0) throw new Malformed(this.s);
      n = n * 62 + d;
    }
  }

  /** Optional `s<base62>` disambiguator. */
  disambiguator() {
    return this.eat('s') ? this.base62() + 1 : 0;
  }

  /** `{ dis, name }`: an identifier with its disambiguator. */
  identifier() {
    const dis = this.disambiguator();
    const puny = this.eat('u');
    const digits = /^\d+/.exec(this.s.slice(this.i));
    if (!digits) throw new Malformed(this.s);
    this.i += digits[0].length;
    this.eat('_');
    const len = Number(digits[0]);
    if (this.i + len > this.s.length) throw new Malformed(this.s);
    const id = this.s.slice(this.i, this.i + len);
    this.i += len;
    return { dis, name: puny ? `{punycode ${id}}` : id };
  }

  name() {
    return this.identifier().name;
  }

  /** Reads what a backref points at with `read`, then comes back. */
  backref(read) {
    const at = this.base62() + 2;
    if (at >= this.i) throw new Malformed(this.s);
    const here = this.i;
    this.i = at;
    const out = read();
    this.i = here;
    return out;
  }

  guard(read) {
    if (++this.depth > 200) throw new Malformed(this.s);
    try {
      return read();
    } finally {
      this.depth--;
    }
  }

  symbol() {
    if (/\d/.test(this.peek() ?? '')) this.base62(); // encoding version
    const path = this.path();
    // An instantiating crate may follow; it is not part of the name.
    return path;
  }

  /** A path; `value` when it names a value (generic arguments as `::<…>`), else a type (`<…>`). */
  path(value = true) {
    return this.guard(() => {
      const tag = this.next();
      switch (tag) {
        case 'C':
          return this.name();
        case 'M': {
          this.disambiguator();
          this.path(); // impl path: where the impl is, not part of the name
          return `<${this.type()}>`;
        }
        case 'X': {
          this.disambiguator();
          this.path();
          const self = this.type();
          return `<${self} as ${this.path()}>`;
        }
        case 'Y': {
          const self = this.type();
          return `<${self} as ${this.path()}>`;
        }
        case 'N': {
          const ns = this.next();
          const parent = this.path();
          const { dis, name } = this.identifier();
          if (ns === 'C') return `${parent}::{closure#${dis}}`;
          if (ns === 'S') return `${parent}::{shim:${name}#${dis}}`;
          if (ns >= 'A' && ns <= 'Z') return `${parent}::{${ns}:${name}#${dis}}`;
          return `${parent}::${name}`;
        }
        case 'I': {
          const base = this.path(value);
          const args = [];
          while (!this.eat('E')) args.push(this.genericArg());
          return `${base}${value ? '::' : ''}<${args.join(', ')}>`;
        }
        case 'B':
          return this.backref(() => this.path(value));
        default:
          throw new Malformed(this.s);
      }
    });
  }

  genericArg() {
    if (this.eat('L')) {
      this.base62();
      return "'_";
    }
    if (this.eat('K')) return this.constant();
    return this.type();
  }

  type() {
    return this.guard(() => {
      const c = this.peek();
      if (c !== undefined && BASIC[c] !== undefined) {
        this.i++;
        return BASIC[c];
      }
      this.i++;
      switch (c) {
        case 'A': {
          const t = this.type();
          return `[${t}; ${this.constant()}]`;
        }
        case 'S':
          return `[${this.type()}]`;
        case 'T': {
          const items = [];
          while (!this.eat('E')) items.push(this.type());
          return items.length === 1 ? `(${items[0]},)` : `(${items.join(', ')})`;
        }
        case 'R':
        case 'Q': {
          if (this.eat('L')) this.base62();
          return `&${c === 'Q' ? 'mut ' : ''}${this.type()}`;
        }
        case 'P':
          return `*const ${this.type()}`;
        case 'O':
          return `*mut ${this.type()}`;
        case 'F':
          return this.fnSig();
        case 'D': {
          if (this.eat('G')) this.base62();
          const traits = [];
          while (!this.eat('E')) {
            let t = this.path(false);
            while (this.eat('p')) t += `<${this.name()} = ${this.type()}>`;
            traits.push(t);
          }
          if (!this.eat('L')) throw new Malformed(this.s);
          this.base62();
          return `dyn ${traits.join(' + ')}`;
        }
        case 'B':
          return this.backref(() => this.type());
        default:
          this.i--;
          return this.path(false);
      }
    });
  }

  fnSig() {
    if (this.eat('G')) this.base62();
    const unsafe = this.eat('U') ? 'unsafe ' : '';
    let abi = '';
    if (this.eat('K')) abi = this.eat('C') ? 'extern "C" ' : `extern "${this.name()}" `;
    const params = [];
    while (!this.eat('E')) params.push(this.type());
    return `${unsafe}${abi}fn(${params.join(', ')}) -> ${this.type()}`;
  }

  constant() {
    return this.guard(() => {
      if (this.eat('p')) return '_';
      if (this.eat('B')) return this.backref(() => this.constant());
      const t = this.next();
      if ('hjmtyoablsxnic'.includes(t)) {
        const neg = this.eat('n');
        const hex = /^[0-9a-f]*/.exec(this.s.slice(this.i))[0];
        this.i += hex.length;
        if (!this.eat('_')) throw new Malformed(this.s);
        const v = hex === '' ? 0n : BigInt(`0x${hex}`);
        if (t === 'b') return v === 0n ? 'false' : 'true';
        if (t === 'c') return `'${String.fromCodePoint(Number(v))}'`;
        return `${neg ? '-' : ''}${v}`;
      }
      // Structural constants (str, refs, arrays, tuples, ADTs) are not needed here.
      throw new Malformed(this.s);
    });
  }
}

/**
 * The address of the one function symbol in `symbols` (from `parseElf`) whose demangled name is the
 * inherent method `method` of the type `typePath` (`firmware::runtime::Runtime`), whatever its generic
 * arguments, in either scheme: `firmware::runtime::Runtime<…>::apply` (legacy) or
 * `<firmware::runtime::Runtime<…>>::apply`, possibly with `::<…>` after it (v0). Thumb bit cleared.
 * Throws when there is none or more than one: a cost without its function is no cost.
 */
export function findMethod(symbols, typePath, method) {
  const type = typePath.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
  const legacyForm = new RegExp(`^${type}<.*>::${method}$`);
  const v0Form = new RegExp(`^<${type}<.*>>::${method}(::<.*>)?$`);
  const STT_FUNC = 2;
  const hits = symbols.filter((s) => {
    if (s.type !== STT_FUNC) return false;
    const name = demangle(s.name);
    return legacyForm.test(name) || v0Form.test(name);
  });
  const addresses = [...new Set(hits.map((s) => s.value & ~1))];
  if (addresses.length !== 1) {
    const what = addresses.length === 0 ? 'no function' : `${addresses.length} functions`;
    throw new Error(`${what} named ${typePath}<…>::${method} in the image's symbol table (is it #[inline(never)]?)`);
  }
  return addresses[0];
}
