# Writes the documents of issue 14's reproducers into HOSTILE_DIR at
# configure time (the largest are generated rather than kept in the tree).
# Each is run by a cli.hostile.* test (CMakeLists.txt).
set(box [=[{"id":"b","type":"box","size":[10,10,10]}]=])
set(hidden_box [=[{"id":"hb","type":"box","size":[1,1,1],"visible":false}]=])
function(kerf_document name root)
  file(WRITE ${HOSTILE_DIR}/${name}.kerf "{\"format\":\"kerf\",\"version\":1,\"root\":${root}}\n")
endfunction()

# An array whose count product wraps around in 64 bits (4 * 2^62 = 0).
kerf_document(wrapped-count
  "{\"id\":\"a\",\"type\":\"array\",\"count\":[4,4611686018427387904,1],\"step\":[20,0,0],\"children\":[${box}]}")

# A union nested 10,000 levels deep.
set(open "")
foreach(i RANGE 1 9999)
  string(APPEND open "{\"id\":\"u${i}\",\"type\":\"union\",\"children\":[")
endforeach()
string(REPEAT "]}" 9999 close)
kerf_document(deep-union "${open}${box}${close}")

# Two arrays of a million around a hidden node: 10^12 copies of nothing.
kerf_document(hidden-arrays
  "{\"id\":\"a1\",\"type\":\"array\",\"count\":[1000000,1,1],\"step\":[1,0,0],\"children\":[{\"id\":\"a2\",\"type\":\"array\",\"count\":[1,1000000,1],\"step\":[0,1,0],\"children\":[{\"id\":\"g\",\"type\":\"union\",\"children\":[${hidden_box}]}]}]}")

# Forty mirrors nested around a hidden leaf: 2^40 copies.
set(mirrors "${hidden_box}")
foreach(i RANGE 1 40)
  set(mirrors "{\"id\":\"m${i}\",\"type\":\"mirror\",\"normal\":[1,0,0],\"offset\":${i},\"children\":[${mirrors}]}")
endforeach()
kerf_document(hidden-mirrors "{\"id\":\"u\",\"type\":\"union\",\"children\":[${box},${mirrors}]}")

# An extrude profile of 500,000 points.
string(REPEAT "[0,0]," 499999 points)
kerf_document(big-profile "{\"id\":\"e\",\"type\":\"extrude\",\"height\":10,\"profile\":[${points}[1,1]]}")

# Ids that would reach the terminal raw: a newline, ANSI escapes, a NUL.
kerf_document(newline-id [=[{"id":"bad\nid","type":"sphere","radius":-1}]=])
kerf_document(ansi-id [=[{"id":"\u001b[31mred\u001b[0m","type":"sphere","radius":-1}]=])
kerf_document(nul-id [=[{"id":"a\u0000b","type":"sphere","radius":-1}]=])

# A 1e308 mm box: too large, not empty.
kerf_document(huge-box [=[{"id":"b","type":"box","size":[1e308,1e308,1e308]}]=])

# Parts that exist, for requests that cannot be met: an 1800 mm panel, a
# veneer, a part a kilometre from the origin, 2000 pegs, a small blended part.
kerf_document(panel [=[{"id":"panel","type":"box","size":[1800,600,18],"round":1}]=])
kerf_document(veneer [=[{"id":"veneer","type":"box","size":[600,400,0.6]}]=])
kerf_document(far [=[{"id":"far","type":"box","size":[500,300,18],"transform":{"translate":[1000000,0,0]}}]=])
kerf_document(pegs [=[{"id":"pegs","type":"array","count":[50,40,1],"step":[12,12,0],"children":[{"id":"peg","type":"cylinder","radius":3,"height":30}]}]=])
kerf_document(blended [=[{"id":"u","type":"union","blend":3,"children":[{"id":"s","type":"sphere","radius":10},{"id":"c","type":"cylinder","radius":4,"height":30,"transform":{"rotate":[90,0,0]}}]}]=])

# A document at the copy limit (20,000 spheres, hidden ones counting).
kerf_document(copy-limit [=[{"id":"a","type":"array","count":[100,100,2],"step":[3,3,3],"children":[{"id":"s","type":"sphere","radius":1}]}]=])
