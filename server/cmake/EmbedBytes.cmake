# cmake -DINPUT=file -DOUTPUT=file.inc -P EmbedBytes.cmake: writes the bytes of INPUT as a C
# initializer list ("0x0a,0x1f,...") to include in an array definition.
file(READ "${INPUT}" hex HEX)
string(REGEX REPLACE "([0-9a-f][0-9a-f])" "0x\\1," bytes "${hex}")
file(WRITE "${OUTPUT}" "${bytes}\n")
