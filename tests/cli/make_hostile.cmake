# Writes the hostile scenarios of the CLI tests into OUT (a directory):
# generated at test time, so no megabytes are committed. Each is refused by
# `groundsim run` with exit 2 and a short message naming the path.
set(head "{\"ground\":{\"type\":\"plane\"},")
file(MAKE_DIRECTORY "${OUT}")

# 10^5 nested objects: {"z":{"":{"": ... 1}}} (~500 KB); it overflowed the
# stack in the recursive copy of the document
string(REPEAT "{\"\":" 100000 open)
string(REPEAT "}" 100000 close)
file(WRITE "${OUT}/deep_object.json" "${head}\"vehicle\":{},\"z\":${open}1${close}}")

# the same depth of arrays
string(REPEAT "[" 100000 open)
string(REPEAT "]" 100000 close)
file(WRITE "${OUT}/deep_array.json" "${head}\"vehicle\":{},\"z\":${open}${close}}")

# 50,000 vehicles
string(REPEAT "{}," 49999 many)
file(WRITE "${OUT}/many_vehicles.json" "${head}\"vehicles\":[${many}{}]}")

# 1,000 vehicles on one spot, each named: the overlap check used to list
# 499,500 pairs (83 MB)
set(list "")
foreach(i RANGE 1 999)
  string(APPEND list "{\"name\":\"v${i}\"},")
endforeach()
file(WRITE "${OUT}/overlapping.json" "${head}\"vehicles\":[${list}{\"name\":\"v0\"}]}")

# a 50 MB name (the file is refused by its size before it is read)
string(REPEAT "a" 1024 kb)
string(REPEAT "${kb}" 1024 mb)
string(REPEAT "${mb}" 50 big)
file(WRITE "${OUT}/huge_name.json" "{\"name\":\"${big}\",\"ground\":{\"type\":\"plane\"},\"vehicle\":{}}")

# a 1 MB vehicle name with control characters: within the document size,
# refused by the name's rules, echoed cut to 200 characters and escaped
file(WRITE "${OUT}/long_name.json" "${head}\"vehicle\":{\"name\":\"\\u0000\\u0007\\u001b${mb}\"}}")
